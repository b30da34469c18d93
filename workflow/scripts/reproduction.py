"""Rule reproduction: the paper-vs-ours table (CSV, Markdown, HTML) and the persistence counts."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.figures.reproduction import build, record, writers  # noqa: E402

p, out = snakemake.params, snakemake.output  # noqa: F821
stored = list(snakemake.input.stored_persistence)  # noqa: F821  (render_only: read, not integrated)
table, persistence = build.run(
    s.results_dir,
    p.config_name,
    dict(p.thresholds),
    p.settings,
    p.near,
    p.limit,
    p.learners,
    p.coopt,
    p.survey,
    p.screen,
    p.text_sweep,
    stored_persistence=stored[0] if stored else None,
)
writers.write(table, out.csv, out.md, out.html, p.config_name)
pers_path = stored[0] if stored else out.persistence
if not stored:
    persistence.to_csv(pers_path, index=False)
extra = [f"{s.results_dir}/learners/correlations.csv"] if p.learners else []
extra += [f"{s.results_dir}/coopt/{n}.csv" for n in ("summary", "landscape")] if p.coopt is not None else []
extra += [f"{s.results_dir}/{s.survey.folder}/metrics.csv"] if p.survey else []
screen = [f"{b['bundle']}/{b['model']}/metrics.csv" for b in (p.screen or {}).values()]
screen += [f"{p.text_sweep}/theory/metrics.csv"] if p.text_sweep else []
record.write_record(s.results_dir, list(p.thresholds), [out.csv, out.md, out.html, pers_path], extra, screen)
