"""The four-synapse controller: the two-weight model is its special case u1 = u2 = 0, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from morphlearn.grid import env_starts, positions, weights
from morphlearn.theory import TheoryParams, cpu, model

P = TheoryParams()


@pytest.mark.parametrize("integrator", ["dp5", "rk4"])
def test_four_synapse_with_zero_uncrossed_is_bit_identical_to_two_synapse(integrator: str) -> None:
    p = TheoryParams(integrator=integrator, dt=0.05)
    rng = np.random.default_rng(7)
    nd = 6
    # grid designs (the canonical one among them) and continuous ones; grid and off-grid weights
    designs = np.vstack(
        [
            [[0.5, 0.5, 0.5, -0.5], [-0.5, -0.375, 0.5, 0.375]],
            rng.uniform(-0.5, 0.5, size=(nd - 2, 4)),
        ]
    )
    n = 600
    di = rng.integers(0, nd, n)
    ei = rng.integers(0, 4, n)
    w = np.where(rng.random((n, 2)) < 0.5, rng.choice(weights(21), (n, 2)), rng.uniform(-1, 1, (n, 2)))
    starts = env_starts(p.r)
    t2, d2, s2 = cpu.points(designs, starts, di, ei, w[:, 0], w[:, 1], **p.kernel_kwargs())
    w4 = np.hstack([w, np.zeros((n, 2))])
    t4, d4, s4 = cpu.points4(designs[di], starts, ei, w4, **p.kernel_kwargs())
    assert s2.tolist() == s4.tolist()
    np.testing.assert_array_equal(t2, t4)  # NaN == NaN here; everything else exactly equal
    np.testing.assert_array_equal(d2, d4)
    assert (s2 == 0).any() and np.isfinite(t2).sum() > 20  # the sample has successes to compare


def test_four_synapse_grid_special_case_matches_the_sweep() -> None:
    design = np.array([[0.5, 0.5, 0.5, -0.5]])
    w = weights(7)
    ft, dm, st, _ = cpu.sweep(design, w, env_starts(P.r), **P.kernel_kwargs())
    e, i, j = np.meshgrid(np.arange(4), np.arange(7), np.arange(7), indexing="ij")
    w4 = np.stack([w[i.ravel()], w[j.ravel()], np.zeros(e.size), np.zeros(e.size)], axis=1)
    t4, d4, s4 = cpu.points4(np.repeat(design, e.size, axis=0), env_starts(P.r), e.ravel(), w4, **P.kernel_kwargs())
    np.testing.assert_array_equal(ft[0].ravel(), t4)
    np.testing.assert_array_equal(dm[0].ravel(), d4)
    assert st[0].ravel().tolist() == s4.tolist()


def test_rhs4_wheels() -> None:
    """Each sensor drives both wheels: right = w1 I1 + u2 I2, left = w2 I2 + u1 I1 (I = 1 / d^2),
    written out here independently of the model."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        x, y = rng.uniform(-4, 4, 2)
        th = rng.uniform(0, 2 * np.pi)
        c, s = np.cos(th), np.sin(th)
        l1x, l1y, l2x, l2y = rng.choice(positions(9), 4)
        w1, w2, u1, u2 = rng.uniform(-1, 1, 4)
        rot = np.array([[c, -s], [s, c]])
        i1 = 1.0 / np.sum((np.array([x, y]) + rot @ [l1x, l1y]) ** 2)
        i2 = 1.0 / np.sum((np.array([x, y]) + rot @ [l2x, l2y]) ** 2)
        right, left = w1 * i1 + u2 * i2, w2 * i2 + u1 * i1
        v, om = (right + left) / 2, right - left
        got = model.rhs4(x, y, c, s, l1x, l1y, l2x, l2y, w1, w2, u1, u2)
        np.testing.assert_allclose(got, (v * c, v * s, -s * om, c * om), rtol=1e-12, atol=1e-12)


def test_uncrossed_weights_change_trajectories() -> None:
    """The four-synapse path really uses u1, u2 (a test of the test above)."""
    design = np.array([[0.5, 0.5, 0.5, -0.5]] * 4)
    e = np.arange(4)
    base = np.tile([0.5, -0.3, 0.0, 0.0], (4, 1))
    other = np.tile([0.5, -0.3, 0.4, -0.2], (4, 1))
    a = cpu.points4(design, env_starts(P.r), e, base, **P.kernel_kwargs())
    b = cpu.points4(design, env_starts(P.r), e, other, **P.kernel_kwargs())
    assert not (np.array_equal(a[0], b[0], equal_nan=True) and np.array_equal(a[1], b[1]))


def test_points4_refuses_bad_shapes() -> None:
    with pytest.raises(ValueError, match=r"coords and w \(n, 4\)"):
        cpu.points4(np.zeros((3, 4)), env_starts(4.0), np.zeros(3, int), np.zeros((3, 2)), **P.kernel_kwargs())
