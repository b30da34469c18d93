"""The stated bound on what one command may simulate without being asked to: episodes x steps.

A physics episode costs its steps (ODE: about 16 us a step of the authors' robot; pybullet and
MuJoCo more), so episodes x steps is the estimate, printed when a bound is passed:

- :data:`DESIGN_BOUND`, one design (``morphlearn design``, and every design of a run): 1e10
  episode-steps, about 70 times the paper's design (4 x 121 x 121 episodes of 2500 steps, 1.46e8);
  ``design --weights 1001`` with 100,000 steps (4e11, about 74 CPU-days in ODE) is past it;
- :data:`RUN_BOUND`, a whole run's physics: 1e12 episode-steps, above the largest preset
  (``config/full.yaml``: 6561 pybullet designs, 9.6e11, a cluster job).

Past either, ``morphlearn design`` needs ``--allow-long`` and a run ``allow_long_run: true``.
"""

from __future__ import annotations

from morphlearn.grid import ENV_ANGLES_DEG

DESIGN_BOUND = 10**10
RUN_BOUND = 10**12


def design_estimate(weights: int, steps: int) -> int:
    """Episode-steps of one design at most (every cell simulated to its last step)."""
    return len(ENV_ANGLES_DEG) * int(weights) ** 2 * int(steps)


def refusal(what: str, designs: int, weights: int, steps: int, flag: str) -> str | None:
    """Why ``designs`` designs of ``weights`` x ``weights`` controllers and ``steps`` steps are
    more than a command simulates unasked (None: they are not): the estimate and the flag."""
    one = design_estimate(weights, steps)
    total = designs * one
    if one <= DESIGN_BOUND and total <= RUN_BOUND:
        return None
    bound = f"one design's bound {DESIGN_BOUND:.0e}" if one > DESIGN_BOUND else f"a run's bound {RUN_BOUND:.0e}"
    return (
        f"{what}: {designs} design(s) x {len(ENV_ANGLES_DEG)} x {weights} x {weights} episodes x {steps} steps "
        f"= {total:.3g} episode-steps, past {bound} (about {total * 16e-6 / 86400:.3g} CPU-days at ODE's "
        f"16 us a step); allowed: fewer weights, steps or designs, or {flag} to run it anyway"
    )
