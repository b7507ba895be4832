"""The sensitivity study's cases: each lever sets what it names, the open loop obeys its closed-form scalings, and an
interrupted study resumes from its partial file."""

from __future__ import annotations

import numpy as np
import pytest
from trusscodesign.control.closedloop import LoopSettings
from trusscodesign.model import spacecraft
from trusscodesign.study import sensitivity

H = 0.02139


@pytest.fixture(scope="module")
def params():
    return spacecraft.load_parameters()


@pytest.fixture(scope="module")
def open_loop(params):
    """Open-loop J_c of a few loop-setting cases, one model (the cases the scalings below compare)."""
    cases = [("p_max", 0.382), ("p_max", 1.2), ("eps_max", 1e-5), ("u_max", 0.1), ("xi_pma", 2.0), ("effort", "transmitted")]
    rows = sensitivity.study(H, cases, params=params, robust=False)
    return {(r["lever"], r["value"]): r for r in rows}


def test_every_lever_sweeps_its_default_on_both_sides(params) -> None:
    for lever in sensitivity.levers(params).values():
        assert lever.default in lever.values, lever.name
        if lever.numeric:
            v = np.asarray(lever.values, dtype=float)
            assert v.min() < lever.default < v.max(), lever.name  # two-sided
            assert np.all(np.diff(v) > 0), lever.name
        assert bool(lever.setting) != bool(lever.model), lever.name


def test_a_case_changes_only_its_own_input(params) -> None:
    settings = LoopSettings.from_parameters(params)
    table = sensitivity.levers(params)
    p, s = sensitivity.case_inputs(table["truss_damping_stiffness"], 1e-4, params, settings)
    assert (p["truss"]["damping"], p["truss"]["damping_model"]) == (1e-4, "stiffness") and s == settings
    assert params["truss"]["damping"] == 1e-3  # the caller's parameters are not edited
    p, s = sensitivity.case_inputs(table["panel_frame"], "literal", params, settings)
    assert p["choices"]["panel_turn_z_deg"] == {"SP1": 0.0, "SP2": 0.0}
    p, s = sensitivity.case_inputs(table["t_delta"], 0.03, params, settings)
    assert p is params and s == settings.replace(t_delta=0.03)
    with pytest.raises(ValueError, match="panel_frame must be one of"):
        sensitivity.case_inputs(table["panel_frame"], "sideways", params, settings)


def test_bad_cases_are_refused_before_any_work(params, monkeypatch) -> None:
    monkeypatch.setattr(sensitivity.design, "models_at", lambda *a, **k: pytest.fail("a model was built"))
    with pytest.raises(ValueError, match=r"unknown levers \['u_maximum'\]"):
        sensitivity.study(H, [("u_max", 5.0), ("u_maximum", 5.0)], params=params)
    with pytest.raises(ValueError, match=r"lever u_max at -5.0 \(effort bound .*u_max must be a finite positive number"):
        sensitivity.study(H, [("t_delta", 0.03), ("u_max", -5.0)], params=params)
    with pytest.raises(ValueError, match="h must be"):
        sensitivity.study(0.5, [("u_max", 5.0)], params=params)


def test_the_open_loop_scales_as_p_max_over_eps_max(open_loop) -> None:
    """With the PMAs passive the loop is linear in the disturbance and the RPE weight is 1/eps_max: closed form."""
    j = {k: r["open_loop_J_c"] for k, r in open_loop.items()}
    assert j[("p_max", 1.2)] / j[("p_max", 0.382)] == pytest.approx(1.2 / 0.382, rel=1e-6)
    assert j[("eps_max", 1e-5)] / j[("p_max", 0.382)] == pytest.approx(5.0, rel=1e-6)
    assert open_loop[("p_max", 1.2)]["open_loop_omega"] == pytest.approx(open_loop[("p_max", 0.382)]["open_loop_omega"], rel=1e-6)


def test_the_open_loop_does_not_depend_on_the_pma_settings(open_loop) -> None:
    """K_PMA = 0: no command, so neither the effort bound, the PMA filter nor the effort's definition can act."""
    base = open_loop[("p_max", 0.382)]["open_loop_J_c"]
    for case in (("u_max", 0.1), ("xi_pma", 2.0), ("effort", "transmitted")):
        assert open_loop[case]["open_loop_J_c"] == pytest.approx(base, rel=1e-9), case


def test_an_interrupted_study_resumes_from_its_partial_file(params, tmp_path, monkeypatch) -> None:
    partial = tmp_path / "sens.partial.json"
    cases = [("t_delta", 0.01), ("t_delta", 0.1)]

    def stop_after_first(it):
        for k, item in enumerate(it):
            if k == 1:
                raise KeyboardInterrupt
            yield item

    with pytest.raises(KeyboardInterrupt):
        sensitivity.study(H, cases, params=params, robust=False, partial=partial, progress=stop_after_first)
    assert partial.exists()
    calls = []
    real = sensitivity.evaluate_case
    monkeypatch.setattr(sensitivity, "evaluate_case", lambda h, ch, *a: calls.append(*ch.values()) or real(h, ch, *a))
    rows = sensitivity.study(H, cases, params=params, robust=False, partial=partial)
    assert calls == [0.1] and [r["value"] for r in rows] == [0.01, 0.1]
    assert not partial.exists()  # removed once complete
    # another setting of the other levers: nothing reused
    sensitivity.study(H, cases[:1], params=params, settings=LoopSettings.from_parameters(params).replace(u_max=5.0),
                      robust=False, partial=partial)
    assert calls == [0.1, 0.01]


def test_cases_with_the_same_inputs_are_evaluated_once(params, monkeypatch) -> None:
    """Every lever's default is the same spacecraft and loop: one evaluation, reported under each lever."""
    calls = []
    real = sensitivity.evaluate_case
    monkeypatch.setattr(sensitivity, "evaluate_case", lambda h, ch, *a: calls.append(*ch) or real(h, ch, *a))
    cases = [("u_max", 15.0), ("t_delta", 0.003), ("truss_damping", 1e-3), ("truss_damping_stiffness", 1e-3)]
    rows = sensitivity.study(H, cases, params=params, robust=False)
    assert calls == ["u_max", "truss_damping_stiffness"]
    assert [(r["lever"], r["value"], r["default"]) for r in rows] == [(*c, True) for c in cases]
    assert rows[0]["open_loop_J_c"] == rows[1]["open_loop_J_c"] == rows[2]["open_loop_J_c"] != rows[3]["open_loop_J_c"]


def test_a_combined_case_sets_every_lever_it_names(params, monkeypatch) -> None:
    """Several levers at once (the calibration's cases): each sets its own input, in one evaluation; conflicting or
    bad levers are refused, naming the lever and its unit, before any model is built."""
    settings = LoopSettings.from_parameters(params)
    p, s = sensitivity.combined_inputs({"antenna_node": "N17", "truss_damping": 2.5e-4, "u_max": 0.3}, params, settings)
    assert (p["antenna"]["node"], p["truss"]["damping"], p["truss"]["damping_model"]) == ("N17", 2.5e-4, "clamped_modes")
    assert s == settings.replace(u_max=0.3) and params["antenna"]["node"] == "N20"
    monkeypatch.setattr(sensitivity.design, "models_at", lambda *a, **k: pytest.fail("a model was built"))
    with pytest.raises(ValueError, match="truss_damping and truss_damping_stiffness both set truss_damping"):
        sensitivity.study(H, [{"truss_damping": 1e-4, "truss_damping_stiffness": 1e-4}], params=params)
    with pytest.raises(ValueError, match=r"lever t_delta at -1.0 \(RPE window .*\[s\]\)"):
        sensitivity.study(H, [("u_max", 5.0), {"u_max": 1.0, "t_delta": -1.0}], params=params)
    with pytest.raises(ValueError, match="at least one lever"):
        sensitivity.study(H, [{}], params=params)


def test_a_combined_case_is_the_same_as_its_levers_applied_in_turn(params, monkeypatch) -> None:
    """The combined case {p_max, eps_max} of the open loop is the closed form of both scalings together, and it is
    reported with its levers and values."""
    rows = sensitivity.study(H, [("p_max", 0.382), {"p_max": 1.2, "eps_max": 1e-5}], params=params, robust=False)
    assert rows[1]["open_loop_J_c"] / rows[0]["open_loop_J_c"] == pytest.approx(1.2 / 0.382 * 5.0, rel=1e-6)
    assert (rows[1]["lever"], rows[1]["value"], rows[1]["default"]) == ("p_max+eps_max", {"p_max": 1.2, "eps_max": 1e-5}, False)


@pytest.mark.parametrize("name", ["paper_calibrated", "paper_match"])
def test_a_presets_case_gives_the_presets_inputs(name):
    stated, want = spacecraft.load_parameters(), spacecraft.preset_parameters(name)
    case = sensitivity.preset_case(name)
    p, s = sensitivity.combined_inputs(case, stated, LoopSettings.from_parameters(stated))
    assert spacecraft.model_inputs(p) == spacecraft.model_inputs(want) and s == LoopSettings.from_parameters(want)
    assert spacecraft.model_inputs(p) != spacecraft.model_inputs(stated) or s != LoopSettings.from_parameters(stated)


def test_a_preset_entry_no_lever_sets_is_refused(monkeypatch):
    monkeypatch.setattr(spacecraft, "load_preset", lambda name: {"model": {"antenna_node": "N17", "hub_mass": 5.0}})
    with pytest.raises(ValueError, match=r"preset 'x': no lever sets its entries \['hub_mass'\]"):
        sensitivity.preset_case("x")


def test_the_conventions_read_the_bounds_and_the_preset_keeps_its_plain_levers(params) -> None:
    """u read as a proof-mass acceleration bounds the force at m u_max (0.1 kg x 15 = 1.5 N); p_max bounding each torque
    lets their 2-norm reach sqrt(2) p_max; a preset that sets u_max is read by the u_max lever, not the convention's."""
    settings = LoopSettings.from_parameters(params)
    table = sensitivity.levers(params)
    _, s = sensitivity.case_inputs(table["u_convention"], "proof-mass acceleration", params, settings)
    assert s.u_max == pytest.approx(1.5)
    _, s = sensitivity.case_inputs(table["p_max_convention"], "each torque", params, settings)
    assert s.p_max == pytest.approx(0.382 * np.sqrt(2))
    assert sensitivity.preset_case("paper_calibrated", params)["u_max"] == 0.1
    with pytest.raises(ValueError, match="levers u_max and u_convention both set u_max"):
        sensitivity.combined_inputs({"u_max": 1.0, "u_convention": "force"}, params, settings)
