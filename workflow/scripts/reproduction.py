"""Rule reproduction: the paper-vs-ours table (CSV, Markdown, HTML) and the persistence counts."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.figures import reproduction  # noqa: E402

p, out = snakemake.params, snakemake.output  # noqa: F821
table, persistence = reproduction.run(
    s.results_dir, p.config_name, dict(p.thresholds), p.settings, p.near, p.limit, p.learners, p.coopt, p.survey
)
reproduction.write(table, out.csv, out.md, out.html)
persistence.to_csv(out.persistence, index=False)
extra = [f"{s.results_dir}/learners/correlations.csv"] if p.learners else []
extra += [f"{s.results_dir}/coopt/{n}.csv" for n in ("summary", "landscape")] if p.coopt is not None else []
extra += [f"{s.results_dir}/{s.survey.folder}/metrics.csv"] if p.survey else []
reproduction.write_record(s.results_dir, list(p.thresholds), [out.csv, out.md, out.html, out.persistence], extra)
