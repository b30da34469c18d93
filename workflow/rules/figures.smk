# Figures (one papermill notebook each, listed in morphlearn.figures.registry), the reproduction
# table, and what the report shows. One rule per figure, so that a figure's caption file can be its
# report caption and editing its notebook, the shared style or a package module it imports (all
# inputs) re-renders only that figure. Outputs are update(): Snakemake backs up the previous ones
# instead of deleting them and restores them when a re-render fails or is refused.


localrules:
    reproduction,
    figures,


for _fig in FIGURES:

    rule:
        name:
            f"figure_{_fig}"
        input:
            notebook=figure_registry.notebook_path(_fig),
            style=figure_registry.STYLE,
            code=figure_modules(_fig),
            data=figure_data(_fig),
        output:
            # update: a failed or refused re-render keeps the previous figure (module docstring)
            png=report(
                update(f"{R}/figures/{_fig}.png"),
                caption=str(Path(f"{R}/figures/{_fig}.caption.md").resolve()),
                category="Figures",
            ),
            pdf=update(f"{R}/figures/{_fig}.pdf"),
            caption=update(f"{R}/figures/{_fig}.caption.md"),
            html=update(f"{R}/figures/{_fig}.html"),
        log:
            notebook=f"{R}/logs/figures/{_fig}.ipynb",
            text=f"{R}/logs/figures/{_fig}.log",
        benchmark:
            f"{R}/benchmarks/figures/{_fig}.tsv"
        localrule: True
        conda:
            "../../envs/figures.yaml"
        params:
            fig=_fig,
            parameters=figure_parameters(_fig),
            # The rerun trigger: Snakemake does not compare params that are functions of input or
            # output (as `parameters` is), so the figure's options also go in as plain text.
            options=json.dumps(FIGURE_OPTIONS[_fig], sort_keys=True),
        shell:
            # the package of this checkout, relative (the workflow runs from its root): an absolute
            # path would change, and re-render every figure, whenever the project is moved or copied
            "(export PYTHONPATH=src${{PYTHONPATH:+:$PYTHONPATH}}; "
            "papermill {input.notebook:q} {log.notebook:q} -y {params.parameters:q} && "
            'jupyter nbconvert --to html --log-level WARN --output-dir "$(dirname {output.html:q})" '
            "--output {params.fig} {log.notebook:q}) > {log.text:q} 2>&1"


rule reproduction:
    input:
        **{
            f"{m}_{n}": f"{R}/{m}/{n}"
            for m in MODELS
            for n in ("metrics.csv", "merged.zarr")
        },
        # like a figure's: the package modules the script and every registered stage import, so a
        # code edit re-runs it
        code=figure_registry.reproduction_code(
            "workflow/scripts/reproduction.py", "src"
        ),
        # beyond the paper: the learner stage's correlations, when it runs
        learners=([f"{R}/learners/correlations.csv"] if S.learners.enabled else []),
        # beyond the paper: the coopt stage's tables, when it runs
        coopt=(
            [f"{R}/coopt/summary.csv", f"{R}/coopt/landscape.csv"]
            if S.coopt.enabled
            else []
        ),
        # the physics survey read from its bundle (survey_from), when set
        survey=SURVEY_FILES,
        # the screen and its refinement, read where they are (screen_from), when set
        screen=figure_options.screen_files(S),
        # the second theory sweep, read where it is (text_sweep_from), when set
        text_sweep=figure_options.text_sweep_files(S),
        # render_only: the stored persistence table, not integrated again
        stored_persistence=([f"{R}/persistence.csv"] if STORED_PERSISTENCE else []),
    output:
        # made unless render_only reads the stored one (input stored_persistence)
        **(
            {}
            if STORED_PERSISTENCE
            else {"persistence": update(f"{R}/persistence.csv")}
        ),
        csv=update(f"{R}/reproduction.csv"),
        md=update(f"{R}/reproduction.md"),
        html=report(
            update(f"{R}/reproduction.html"),
            caption="../report/reproduction.rst",
            category="Reproduction",
        ),
        # custody: the digests of the tables read and of these files (reproduction.record.write_record)
        provenance=update(f"{R}/reproduction.provenance.json"),
    log:
        f"{R}/logs/reproduction.log",
    benchmark:
        f"{R}/benchmarks/reproduction.tsv"
    conda:
        "../../envs/figures.yaml"
    params:
        config_name=" + ".join(Path(f).name for f in reversed(workflow.configfiles)),
        learners=S.learners.enabled,
        coopt=S.coopt.sigmas[0] if S.coopt.enabled else None,
        near=S.figures.near_distance,
        limit=S.figures.persistence_controllers,
        settings=figure_options.trajectory_settings(S),
        thresholds={m: models.get(m).thresholds(S).__dict__ for m in MODELS},
        survey=figure_options.survey_option(S),
        screen=figure_options.screen_option(S),
        text_sweep=S.text_sweep,
    script:
        "../scripts/reproduction.py"


rule figures:
    input:
        FIGURE_TARGETS,
