"""The authors' robot's contact slip and constraint mixing as body parameters (config/authors_body.yaml):
read by ODE's C core and the reduced model, bounded by the schema, recorded for the models that
read them and only those; defaults give the outcomes the constants gave."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ode_only_config

from morphlearn.grid import weights
from morphlearn.physics.params import EmpiricalParams, load_params

ROOT = Path(__file__).resolve().parents[1]
BODY = load_params(ROOT / "config/authors_body.yaml")
L1, L2 = (-0.5, -0.375), (0.125, -0.25)
#: cells (env, i_w1, i_w2) of that design at 121 weights: successes of the reduced model in each
#: environment (the last a generalist) and a failure
CELLS = np.array([[0, 99, 88], [1, 14, 26], [2, 38, 15], [3, 116, 97], [0, 60, 60]])


#: their outcomes (first success step, steps, closest approach as a hex double) on 0a70f09, where
#: the slip was a constant (0.01) and ODE's world kept its own ERP and CFM (never set)
BEFORE = {
    "ode": ([1444, 498, 518, 1507, -1], [1444, 498, 518, 1507, 2500],
            ["0x1.eba3a9b1facb2p-1", "0x1.e9bdcea75b248p-1", "0x1.e6734fc775761p-1", "0x1.e58bdcff2894ap-1",
             "0x1.6a09e667f3bcdp+2"]),
    "reduced": ([1450, 499, 518, 1505, -1], [1450, 499, 518, 1505, 2500],
                ["0x1.ebeefede3f6ccp-1", "0x1.e152753615ecbp-1", "0x1.e9dc3c834f7f4p-1", "0x1.e5d7684a09588p-1",
                 "0x1.6a09e667f3bcdp+2"]),
}  # fmt: skip


def _run(engine: str, p: EmpiricalParams) -> np.ndarray:
    if engine == "ode":
        pytest.importorskip("morphlearn.ode._core")
        from morphlearn.ode.core import run
    else:
        from morphlearn.reduced.core import run
    w = weights(121)
    ep, _ = run(p, L1, L2, np.stack([w[CELLS[:, 1]], w[CELLS[:, 2]]], 1), CELLS[:, 0])
    return np.stack([ep.first_step, ep.steps, ep.min_dist.view(np.int64)])


def test_the_body_file_holds_the_authors_and_odes_values() -> None:
    assert (BODY.contact_slip, BODY.erp, BODY.cfm, BODY.motor_cfm) == (0.01, 0.2, 1e-10, 1e-5)
    assert BODY == EmpiricalParams(**{**EmpiricalParams().to_dict(), **BODY.to_dict()})


@pytest.mark.parametrize(
    ("key", "value", "allowed"),
    [("contact_slip", 0.0, "number > 0 and <= 1"), ("erp", 1.5, "number >= 0 and <= 1"), ("cfm", -1e-9, "> 0")],
)
def test_out_of_range_values_are_refused_in_one_line(key: str, value: float, allowed: str) -> None:
    with pytest.raises(ValueError, match=rf"^{key} = {value!r} is out of range; allowed: .*{allowed}"):
        BODY.replace(**{key: value})


@pytest.mark.parametrize("engine", ["ode", "reduced"])
def test_the_defaults_give_the_outcomes_of_the_constants_bit_for_bit(engine: str) -> None:
    first, steps, dist = BEFORE[engine]
    got = _run(engine, BODY)
    assert got[0].tolist() == first and got[1].tolist() == steps
    assert [float(x).hex() for x in got[2].view(np.float64)] == dist


@pytest.mark.parametrize("engine", ["ode", "reduced"])
def test_half_the_slip_is_a_body_value_each_engine_reads(engine: str) -> None:
    base = _run(engine, BODY)
    assert not np.array_equal(_run(engine, BODY.replace(contact_slip=0.005)), base)
    mixing = {"ode": {"cfm": 1e-5}, "reduced": {"motor_cfm": 1e-3}}[engine]
    assert not np.array_equal(_run(engine, BODY.replace(**mixing)), base)
    # what the engine does not read changes nothing
    unread = {"ode": {"motor_cfm": 1e-3}, "reduced": {"erp": 0.5, "cfm": 1e-5}}[engine]
    np.testing.assert_array_equal(_run(engine, BODY.replace(**unread)), base)


def test_records_name_what_each_model_reads() -> None:
    from morphlearn import models

    pytest.importorskip("morphlearn.ode._core")
    ode = ode_only_config(
        {"weights": 11, "designs": [[[-0.5, 0.125], [0.5, -0.375]]]}, {"positions_per_axis": 9, "weights": 11}
    )
    rec = ode.models["ode"].science["params"]
    assert (rec["contact_slip"], rec["erp"], rec["cfm"]) == (0.01, 0.2, 1e-10)
    assert not {"wheel_friction", "solver_iterations", "motor_cfm"} & set(rec)
    red = models.get("reduced").recorded_params
    assert {"contact_slip", "motor_cfm"} <= set(red) and not {
        "wheel_friction",
        "solver_iterations",
        "erp",
        "cfm",
    } & set(red)
    # pybullet and MuJoCo do not read them: their records are as before
    for name in ("empirical", "mujoco"):
        assert not {"contact_slip", "erp", "cfm", "motor_cfm"} & set(models.get(name).recorded_params)
    # a body at the defaults lists them nowhere else (the digests of records made before hold)
    assert not {"contact_slip", "erp", "cfm", "motor_cfm"} & set(BODY.to_dict())
    assert BODY.replace(contact_slip=0.005).to_dict()["contact_slip"] == 0.005
