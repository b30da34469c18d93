# The results bundle: a compact, checksummed copy of this run's results for committing
# (src/morphlearn/bundles/make.py). Not part of `all`: `snakemake bundle` with a config that sets
# bundle_dir (config/paper.yaml).


localrules:
    bundle,


BUNDLE_CONFIGS = [os.path.relpath(f) for f in workflow.configfiles]
# Before anything runs: bundle_dir may only be absent, empty, or this config's own bundle.
if workflow.is_main_process:
    try:
        # the config locations check-bundle reads, said before anything runs
        if S.bundle_dir:
            bundlemod.check_config_locations(BUNDLE_CONFIGS)
        bundlemod.check_target(S.bundle_dir, bundlemod.made_by(BUNDLE_CONFIGS, R))
    except bundlemod.BundleError as err:
        print(f"morphlearn: {err}", file=sys.stderr)
        sys.exit(2)
    # said before hours of simulation, not only when the bundle rule refuses them
    commit = provenance.git_commit()
    if provenance.uncommitted(commit):
        print(
            f"morphlearn: note: the worktree is at {commit}: the bundle rule refuses results "
            "simulated from uncommitted code (commit first; bundle_dir is set)",
            file=sys.stderr,
        )


rule bundle:
    input:
        FIGURE_TARGETS,
        *(f"{R}/{m}/{n}" for m in MODELS for n in ("metrics.csv", "merged.zarr")),
        *SURVEY_FILES,
        summary=f"{R}/summary.md",
    output:
        # update: Snakemake keeps (and on failure restores) this config's previous bundle instead
        # of deleting it first; the build writes aside and swaps only when complete.
        update(directory(S.bundle_dir)),
    log:
        f"{R}/logs/bundle.log",
    benchmark:
        f"{R}/benchmarks/bundle.tsv"
    conda:
        "../../envs/figures.yaml"
    params:
        results=R,
        top=S.analysis.top,
        designs_kept=S.bundle_designs,
        configs=BUNDLE_CONFIGS,
    script:
        "../scripts/bundle.py"
