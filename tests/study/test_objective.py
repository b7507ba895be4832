"""The co-design's objective at one section side h: a stored evaluation recomputed."""

import numpy as np
from trusscodesign.control.closedloop import LoopSettings
from trusscodesign.infra import paths, results
from trusscodesign.model import spacecraft
from trusscodesign.study import objective


def test_notebook_07s_stored_grid_point_recomputes_to_the_last_bit():
    """A point of notebook 07's stored grid on the stated values (a cold synthesis with notebook 07's options, h = 2.85
    cm, the grid's quickest) recomputed from the grid's stored key by today's code: the same J_c, Z_c, gain and
    scenario set, to the last bit."""
    grid = results.read_json(paths.ROOT / "data" / "results" / "07_grid.json")
    key = grid["key"]
    options = objective.synthesis_options(True, "ball", "least_change")
    assert options.key() == key["synthesis"] and key["parameters"] == spacecraft.parameters_fingerprint()
    rec = next(r for r in grid["records"] if abs(r["h"] - 0.0285) < 1e-12)
    out = objective.evaluate_particle(rec["h"], None, LoopSettings(**key["settings"]), synthesis_options=options)
    assert (out["J_c"], out["Z_c"], out["iterations"], out["status"]) == (rec["J_c"], rec["Z_c"], rec["iterations"], "ok")
    assert np.array_equal(out["gain"], rec["gain"]) and out["scenarios"] == rec["scenarios"]


def test_a_particle_with_sides_by_member_group_is_recorded_with_them():
    """The record keeps the sides by key; its mass is theirs; a failure or a side out of range is a failed particle."""
    from trusscodesign.model import spacecraft
    from trusscodesign.study import objective

    sides = {"longerons": 0.025, "all": 0.02}
    r = objective.evaluate_particle(sides, fail=True)
    assert r["h"] == sides and r["mass"] == spacecraft.truss_mass(sides)
    assert r["status"].startswith("failed: RuntimeError: injected") and r["f"] == r["mass"] / objective.M0_PAPER + 10
    bad = objective.evaluate_particle({"longerons": 0.3, "all": 0.02})
    assert bad["status"].startswith("failed: ValueError: sides['longerons'] must be a section side") and bad["f"] == float("inf")
    lost = objective.lost_evaluation(sides, "worker died")
    assert lost["h"] == sides and lost["status"] == "failed: worker died"
