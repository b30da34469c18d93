"""How the rows write a count and the configuration their numbers come from."""

from __future__ import annotations

from morphlearn.figures import data as fd
from morphlearn.figures.caption import resolution_note, science_summary


def frac(n: int, m: int) -> str:
    """ "n of m (share %)", the share to 3 significant digits: at a fixed 2 decimals 1 of 14641
    printed "0.01 %" beside the paper's "0.0068 %", equal values that looked different."""
    return f"{n} of {m} ({100 * n / m:.3g} %)"


def config_note(res: fd.ModelResults | None, config_name: str) -> str:
    if res is None:
        return config_name
    return f"{config_name}: {resolution_note(res)}; {science_summary(res)}"
