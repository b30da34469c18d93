"""What ``morphlearn design`` writes besides its lines: the outcome arrays (``--save``) and the
design's map (``--plot``), each checked before the simulation starts (a 121 x 121 ODE design is
half an hour of a core: a bad path is refused first, in one line)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from morphlearn import grid as gridmod
from morphlearn.errors import UsageError
from morphlearn.results import DesignResult

#: The formats --plot writes (matplotlib's, by the file's ending).
PLOT_FORMATS = (".png", ".pdf", ".svg")


def check_target(option: str, path: str, endings: tuple[str, ...]) -> Path:
    """The path of a file ``design`` will write: its folder exists, its ending is one allowed."""
    p = Path(path)
    if p.suffix.lower() not in endings:
        raise UsageError(f"{option} {path}: allowed endings {', '.join(endings)}")
    if not p.parent.is_dir():
        raise UsageError(f"{option} {path}: no folder {p.parent} (make it first)")
    if p.is_dir():
        raise UsageError(f"{option} {path}: is a folder; allowed: a file name ending {', '.join(endings)}")
    return p


def save_arrays(path: Path, res: DesignResult, weights: np.ndarray, meta: dict[str, object]) -> None:
    """The design's outcome arrays, each (4, m, m) over (environment, w1, w2): ``first_time`` (NaN:
    no success), ``min_dist``, ``status``; with ``weights`` (the grid of w1 and of w2), ``env_deg``
    (the light's angles) and ``meta`` (the model, the design, the command's options) as strings.
    Written whole or not at all (a temporary file renamed)."""
    arrays = {
        "first_time": res.first_time,
        "min_dist": res.min_dist,
        "status": res.status,
        "weights": np.asarray(weights, dtype=np.float64),
        "env_deg": np.asarray(gridmod.ENV_ANGLES_DEG),
    }
    meta_arrays = {f"meta_{k}": np.asarray(str(v)) for k, v in meta.items()}
    tmp = path.with_name(path.name + ".tmp.npz")
    np.savez_compressed(tmp, **arrays, **meta_arrays)
    tmp.replace(path)


def plot_map(path: Path, res: DesignResult, weights: np.ndarray, title: str) -> None:
    """The design's map: environments solved by each controller (w1, w2), generalists cyan (a few
    ringed), as the paper's Fig. 6; the same bytes for the same outcomes (no time stamps)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot as plt

    from morphlearn.figures.draw.matrix import overlap_colorbar, overlap_image

    overlap = (~np.isnan(res.first_time)).sum(axis=0)
    fig, ax = plt.subplots(figsize=(6.4, 4.8), layout="constrained")
    im = overlap_image(ax, overlap, weights, "")
    ax.set_title(title, fontsize=10)
    overlap_colorbar(fig, im, ax)
    meta: dict[str, None] = {
        ".png": {"Software": None},
        ".pdf": {"CreationDate": None, "ModDate": None, "Producer": None},
        ".svg": {"Date": None, "Creator": None},
    }[path.suffix.lower()]
    tmp = path.with_name(path.name + ".tmp" + path.suffix)
    fig.savefig(tmp, dpi=150, metadata=meta, bbox_inches="tight", pad_inches=0.1)
    plt.close(fig)
    tmp.replace(path)
