# The results bundle: a compact, checksummed copy of this run's results for committing
# (src/morphlearn/bundle.py). Not part of `all`: `snakemake bundle` with a config that sets
# bundle_dir (config/paper.yaml).


localrules:
    bundle,


rule bundle:
    input:
        FIGURE_TARGETS,
        *(f"{R}/{m}/{n}" for m in MODELS for n in ("metrics.csv", "merged.zarr")),
        summary=f"{R}/summary.md",
    output:
        directory(S.bundle_dir),
    log:
        f"{R}/logs/bundle.log",
    benchmark:
        f"{R}/benchmarks/bundle.tsv"
    conda:
        "../../envs/figures.yaml"
    params:
        results=R,
        top=S.analysis.top,
        configs=[os.path.relpath(f) for f in workflow.configfiles],
    script:
        "../scripts/bundle.py"
