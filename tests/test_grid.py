import numpy as np
import pytest

from morphlearn import grid


@pytest.mark.parametrize("n", [2, 3, 5, 9, 10, 121])
def test_axis_is_exactly_symmetric(n: int) -> None:
    x = grid.symmetric_linspace(-1.0, 1.0, n)
    assert np.array_equal(x, -x[::-1])
    np.testing.assert_allclose(x, np.linspace(-1, 1, n), atol=1e-15)


def test_paper_grid_sizes() -> None:
    g = grid.DesignGrid(9)
    assert g.size == 6561
    assert len(grid.weights(121)) == 121 and grid.weights(121)[[0, -1]].tolist() == [-1, 1]
    # Mirror pairs: 81 self-mirror designs (l2 = (x1, -y1)), so (6561 + 81) / 2 distinct.
    assert len(g.representatives()) == 3321


def test_index_roundtrip_and_coords() -> None:
    g = grid.DesignGrid(5)
    d = np.arange(g.size)
    assert np.array_equal(g.flat(g.indices(d)), d)
    assert g.index_of((0.5, 0.5), (0.5, -0.5)) == int(g.flat(np.array([4, 4, 4, 0])))
    assert g.coords(g.index_of((-0.5, -0.25), (0.5, 0.25))).tolist() == [-0.5, -0.25, 0.5, 0.25]
    with pytest.raises(ValueError, match=r"l1.y=0.3 is not on the 5-point grid"):
        g.index_of((0.5, 0.3), (0.5, -0.5))


def test_mirror_map() -> None:
    g = grid.DesignGrid(5)
    d = np.arange(g.size)
    m = g.mirror(d)
    assert np.array_equal(g.mirror(m), d)  # an involution
    c, cm = g.coords(d), g.coords(m)
    assert np.array_equal(cm, np.stack([c[:, 2], -c[:, 3], c[:, 0], -c[:, 1]], 1))
    canon = g.index_of((0.5, 0.5), (0.5, -0.5))
    assert g.mirror(canon) == canon  # the canonical design is its own mirror image
    assert [grid.ENV_ANGLES_DEG[k] for k in grid.ENV_MIRROR] == [315, 225, 135, 45]
    # one design or a mirror pair, in either order; any other design is not
    pair = [bool(g.same_pair(a, b)) for a, b in ((3, 3), (3, int(m[3])), (int(m[3]), 3))]
    assert pair == [True, True, True]
    assert sum(g.same_pair(3, b) for b in range(g.size)) == (1 if m[3] == 3 else 2)


def test_env_starts_are_exact_mirror_pairs() -> None:
    s = grid.env_starts(4.0)
    assert np.array_equal(s[list(grid.ENV_MIRROR)], s * [1, -1])
    np.testing.assert_allclose(np.hypot(*s.T), 4.0)
    ang = np.degrees(np.arctan2(*grid.light_positions(4.0)[:, ::-1].T)) % 360
    np.testing.assert_allclose(ang, grid.ENV_ANGLES_DEG)


def test_split_shards() -> None:
    parts = grid.split_shards(np.arange(10), 3)
    assert [len(p) for p in parts] == [4, 3, 3]
    assert np.array_equal(np.concatenate(parts), np.arange(10))
    with pytest.raises(ValueError, match="shards=11 exceeds the 10 designs"):
        grid.split_shards(np.arange(10), 11)
