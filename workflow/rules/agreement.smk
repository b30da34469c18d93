# Each engine and robot against ODE with the authors' robot, design by design (issue 42; beyond the
# paper; config/agreement.yaml, docs/authors_robot.md): from the committed survey bundles
# (agreement.reference, .candidates), the table and the numbers the figure `agreement` draws (a
# registered figure: morphlearn.figures.registry; its rule in figures.smk). Outputs update(): a
# failed rerun keeps the previous ones.


localrules:
    agreement,


rule agreement:
    input:
        **AGREEMENT.inputs(),
        # the package modules the script imports, so a code edit re-runs it
        code=figure_registry.notebook_modules("workflow/scripts/agreement.py", "src"),
    output:
        table=update(f"{R}/agreement.csv"),
        numbers=update(f"{R}/agreement.json"),
        # custody: the tables' digests and these files' (the figure checks it)
        provenance=update(f"{R}/agreement.provenance.json"),
    log:
        f"{R}/logs/agreement/agreement.log",
    benchmark:
        f"{R}/benchmarks/agreement/agreement.tsv"
    conda:
        "../../envs/analysis.yaml"
    params:
        agreement=AGREEMENT.science(),
    script:
        "../scripts/agreement.py"
