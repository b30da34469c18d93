"""Which run a config asks for, as data: the rule files the Snakefile includes and what its
``rule all`` asks for. The Snakefile reads one :class:`Run` instead of switching between modes.

Four kinds, one a config: the paper's workflow (simulate, merge, metrics, figures, the reproduction
table, bundles), the named scenarios (docs/scenarios.md), the engine agreement (config/agreement.yaml)
and the engine comparison (config/engines.yaml). A ``render_only`` run includes no rule that
simulates, merges or computes metrics: it renders from stored results.
"""

from __future__ import annotations

from dataclasses import dataclass

from morphlearn.config import ConfigError
from morphlearn.settings import Settings

#: What each figure rule writes (workflow/rules/figures.smk).
FIGURE_EXTENSIONS = ("png", "pdf", "html")


@dataclass(frozen=True)
class Run:
    """One kind of run: ``rules`` are workflow/rules/<name>.smk in include order; ``figures``: a
    stage's targets are these figures alone (and what its rule file adds: the scenarios'
    comparison); None: the paper's workflow, whose targets common.smk names."""

    kind: str
    rules: tuple[str, ...]
    figures: tuple[str, ...] | None = None

    @property
    def rule_files(self) -> list[str]:
        """The rule files, relative to the Snakefile."""
        return [f"workflow/rules/{r}.smk" for r in self.rules]

    def figure_targets(self, results_dir: str) -> list[str]:
        """The stage's figures in every format its figure rule writes."""
        return [f"{results_dir}/figures/{f}.{ext}" for f in self.figures or () for ext in FIGURE_EXTENSIONS]


#: The stages that replace the paper's workflow when set: (kind, whether the config sets it).
STAGES = (
    ("scenarios", lambda s: s.scenarios is not None),
    ("agreement", lambda s: s.agreement.enabled),
    ("engines", lambda s: s.engines.enabled),
)
#: What the agreement and the engine comparison make: their figures alone.
STAGE_FIGURES = {"agreement": ("agreement",), "engines": ("engines", "disagreement")}


def run(s: Settings) -> Run:
    """The run ``s`` asks for; ConfigError (one line) when it sets two stages that each replace the
    paper's workflow (before, the first of them won silently)."""
    chosen = [kind for kind, on in STAGES if on(s)]
    if len(chosen) > 1:
        raise ConfigError(
            f"{' and '.join(chosen)} are both set; a run makes one of them (allowed: one of "
            f"{', '.join(k for k, _ in STAGES)}, or none for the paper's workflow)"
        )
    if chosen == ["scenarios"]:
        return Run("scenarios", ("scenarios",), ())  # its targets: the comparison (no figures.smk)
    if chosen:
        kind = chosen[0]
        return Run(kind, (*(() if s.render_only else (kind,)), "figures"), STAGE_FIGURES[kind])
    stages = (
        ()
        if s.render_only
        else (
            "simulate",
            "morphology",
            "analysis",
            *(("learners",) if s.learners.enabled else ()),
            *(("coopt",) if s.coopt.enabled else ()),
            *(("bundle",) if s.bundle_dir else ()),
        )
    )
    return Run("paper", (*stages, "figures"))
