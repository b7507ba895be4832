"""T-truss and spacecraft open loop: masses, orders, FE cross-check, PMA, SADM joint, bad input."""

import json

import numpy as np
import pytest
from trusscodesign.model import bodies, frames, opensees_fe, reduction, spacecraft, statespace, titop, truss

H_VALUES = [0.015, 0.02139, 0.03]
PARAMS = spacecraft.load_parameters()


@pytest.fixture(scope="module")
def nominal():
    return spacecraft.open_loop(0.03)


def test_truss_geometry_and_mass():
    nodes, members = truss.truss_nodes(), truss.truss_members()
    assert len(nodes) == 24 and len(members) == 65 and len({tuple(sorted(m)) for m in members}) == 65
    pos = np.array(list(nodes.values()))
    np.testing.assert_allclose(pos.max(axis=0) - pos.min(axis=0), [1.0, 3.0, 3.0])
    # N17 directly below N20, N20 on the top plane
    np.testing.assert_allclose(nodes["N20"] - nodes["N17"], [0.0, 0.0, 1.0])
    assert nodes["N20"][2] == pos[:, 2].max()
    assert abs(spacecraft.truss_mass(0.03) / 183.11 - 1) < 1e-3


@pytest.mark.parametrize("h", H_VALUES)
def test_dc_gain_mass_equals_sum_of_components(h):
    ol = spacecraft.open_loop(h)
    total = sum(spacecraft.component_masses(h).values())
    assert abs(ol.mass() / total - 1) < 1e-6


def test_orders_and_signals(nominal):
    assert nominal.blocks["truss"].nstates == 1300
    assert nominal.blocks["truss"].nchannels == 36
    assert nominal.blocks["pmas"].nstates == 8 and nominal.blocks["pmas"].nchannels == 16
    assert nominal.blocks["hub"].nchannels == 42 and nominal.blocks["hub"].nstates == 0
    g = nominal.G
    assert (g.nstates, g.ninputs, g.noutputs) == (1324, 12, 20)
    assert g.input_labels == spacecraft.INPUTS and g.output_labels == spacecraft.OUTPUTS


def test_near_zero_poles_are_spurious(nominal):
    g = nominal.G
    split = reduction.split_slow(g.A, g.B, g.C, g.D)
    assert split.n_slow == 540  # 45 loop-closing inversions x 12
    assert split.contribution < 1e-8
    poles = np.linalg.eigvals(split.fast[0])
    assert poles.real.max() < 0  # the remaining (physical) poles are stable
    # the removed part does not change the input-output behaviour
    w = np.logspace(-3, 4, 12)
    full = statespace.frequency_response(g.A, g.B, g.C, g.D, w)
    red = statespace.frequency_response(*split.fast, w)
    assert np.max(np.max(np.abs(full - red), axis=(0, 1)) / np.max(np.abs(full), axis=(0, 1))) < 1e-8


@pytest.mark.parametrize("h", H_VALUES)
def test_clamped_truss_matches_opensees(h):
    sec = titop.Section.square(h)
    model = truss.t_truss(sec)
    p = model.poles()
    f = np.sort(np.abs(p[(p.imag > 0) & (np.abs(p) > 1e-2)]))[:15]
    fe = opensees_fe.frame_frequencies(truss.truss_nodes(), truss.truss_members(), sec, ["N1", "N2", "N3", "N4"], 10, "consistent", 15)
    assert np.all(np.abs(f / fe - 1) < 5e-3)


def test_pma_alone_on_clamped_base():
    pm = PARAMS["pma"]
    model = bodies.pma("N", [0, 0, 0], np.eye(3), pm["casing_mass"], pm["casing_inertia"], pm["r_og"], pm["proof_mass"],
                       pm["stiffness"], pm["damping"])
    p = model.poles()
    w_n = np.sqrt(pm["stiffness"] / pm["proof_mass"])
    zeta = pm["damping"] / (2 * np.sqrt(pm["stiffness"] * pm["proof_mass"]))
    np.testing.assert_allclose(np.abs(p), [w_n, w_n], rtol=1e-12)
    np.testing.assert_allclose(-p.real / np.abs(p), [zeta, zeta], rtol=1e-12)
    dc = model.d - model.c @ np.linalg.solve(model.a, model.b)
    assert np.isclose(dc[6, 6], 1.0 / pm["stiffness"], rtol=1e-12)
    total = pm["casing_mass"] + pm["proof_mass"]
    np.testing.assert_allclose(np.diag(dc)[:3], -total, rtol=1e-12)


def test_sadm_joint_is_a_stiff_damped_spring():
    sp = PARAMS["solar_panel"]
    ch = PARAMS["choices"]
    rot = frames.rot_z(np.pi / 2)
    axis = rot.T @ [1.0, 0.0, 0.0]
    panel = bodies.solar_panel("P6", [1, 0, 0], rot, sp["mass"], sp["r_og"], sp["inertia_g"], sp["omega"], sp["damping"],
                               sp["factors"], axis, ch["sadm_stiffness"], ch["sadm_friction"], label="SP1")
    p = panel.poles()
    assert panel.nstates == 8 and p.real.max() < 0
    # the panel's CoG lies outboard along +x at theta = 0: its rigid mass at P6 couples Ty with Rz like a mass at x = +2
    dc = panel.d - panel.c @ np.linalg.solve(panel.a, panel.b)  # no poles at 0: k > 0
    i = panel.channels("P6")
    d_p6 = -dc[np.ix_(i, i)]
    assert np.isclose(d_p6[0, 0], sp["mass"])
    r_g = np.array([2.0, 0.0, 0.03])
    np.testing.assert_allclose(d_p6[:3, 3:], sp["mass"] * frames.skew(r_g).T, atol=1e-9)
    # a static SADM torque p (hub on panel, about +x) deflects the joint by p / k
    s = panel.channels("SP1")[0]
    assert np.isclose(dc[s, s], 1.0 / ch["sadm_stiffness"], rtol=1e-9)


@pytest.mark.parametrize(
    "kwargs, match",
    [(dict(h=0.0), "h"), (dict(h=-0.01), "h"), (dict(theta=np.inf), "theta"), (dict(hub_mass=-800.0), "hub_mass"),
     (dict(hub_iyy=0.0), "hub_iyy"), (dict(panel_omega1=float("nan")), "panel_omega1")],
)
def test_bad_values_raise(kwargs, match):
    with pytest.raises(ValueError, match=match):
        spacecraft.open_loop(**kwargs)


def test_bad_body_values_raise():
    with pytest.raises(ValueError, match="mass"):
        bodies.rigid_hub(-1.0, np.eye(3), {"P1": [0, 0, 0]})
    with pytest.raises(ValueError, match="inertia"):
        bodies.rigid_appendage(1.0, -np.eye(3), "N", [0, 0, 0])
    with pytest.raises(ValueError, match="stiffness"):
        bodies.pma("N", [0, 0, 0], np.eye(3), 0.5, np.eye(3) * 1e-3, [0, 0.05, 0], 0.1, 0.0, 1.4)
    sp = PARAMS["solar_panel"]
    with pytest.raises(ValueError, match="stiffness"):
        bodies.solar_panel("P6", [1, 0, 0], np.eye(3), sp["mass"], sp["r_og"], sp["inertia_g"], sp["omega"], sp["damping"],
                           sp["factors"], [1, 0, 0], 0.0, 1.0)


@pytest.fixture(scope="module")
def uncertain():
    return spacecraft.open_loop(0.03, uncertain=True)


def test_uncertain_model_occurrences(uncertain):
    occ = uncertain.lft.occurrences()
    # the paper's counts for the hub mass, hub Iyy and first panel frequency
    assert occ["M_SC"] == 3 and occ["Iyy_SC"] == 1 and occ["omega1_SP"] == 4
    # tau: two-sided twice DCM per panel, 16 each (the minimal order of R6(tau) X R6(tau)^T for a generic X)
    assert occ["tau"] == 32
    assert uncertain.lft.shape == (20, 12) and uncertain.G.nstates == 1324


def test_uncertain_model_equals_direct_build_at_draws(uncertain):
    lft = uncertain.lft
    draws = lft.sample(3, rng=7, corners=True) + lft.sample(2, rng=8)
    for delta in draws:
        vals = {k: lft.params[k].from_delta(v) for k, v in delta.items()}
        a, b, c, d = lft.evaluate(delta, normalized=True)
        ref = spacecraft.open_loop(0.03, theta=4 * np.arctan(vals["tau"]), hub_mass=vals["M_SC"], hub_iyy=vals["Iyy_SC"],
                                   panel_omega1=vals["omega1_SP"]).G
        for x, y in ((a, ref.A), (b, ref.B), (c, ref.C), (d, ref.D)):
            assert np.max(np.abs(x - y)) <= 1e-12 * np.max(np.abs(y))
    # the nominal mass is unchanged by the LFT form
    assert abs(uncertain.mass() / sum(spacecraft.component_masses(0.03).values()) - 1) < 1e-9


def test_rotation_lft_is_exact_and_minimal():
    from trusscodesign.model.lft import LFT, Parameter

    tau = Parameter("tau", 0.0, -1.0, 1.0)
    r6 = frames.twice_dcm_lft(tau, frames.rot_z(np.pi / 2))
    assert r6.occurrences() == {"tau": 8}
    for t in (-1.0, -0.2, 0.6, 1.0):
        np.testing.assert_allclose(r6.evaluate({"tau": t})[3], frames.twice_dcm(frames.rot_x(4 * np.arctan(t)) @ frames.rot_z(np.pi / 2)), atol=1e-14)
    # R X R^T for a generic X: the Hankel matrix of its Markov parameters in tau has rank 16 (no smaller exact LFT)
    x = np.random.default_rng(0).normal(size=(6, 6))
    f = r6 @ LFT.constant(x) @ r6.T
    nd = f.n_delta
    m11, m12, m21 = f.d[:nd, :nd], f.d[:nd, nd:], f.d[nd:, :nd]
    markov = [m21 @ np.linalg.matrix_power(m11, k) @ m12 for k in range(2 * nd)]
    hankel = np.block([[markov[i + j] for j in range(nd)] for i in range(nd)])
    sv = np.linalg.svd(hankel, compute_uv=False)
    assert nd == 16 and np.sum(sv > 1e-9 * sv[0]) == 16


def test_a_pma_or_antenna_off_the_truss_ports_is_refused():
    """A PMA on N18 (a truss node the truss model does not expose) was left clamped to the ground: the model built,
    1 PMA short in mass, with no path from its force to the LOS (an independent review)."""
    import copy

    for change in ({"node": "N18"}, {"direction": "z"}):
        p = copy.deepcopy(spacecraft.load_parameters())
        p["choices"]["pma_layout"][0].update(change)
        with pytest.raises(ValueError, match="pma_layout"):
            spacecraft.open_loop(0.03, params=p)
    p = copy.deepcopy(spacecraft.load_parameters())
    p["antenna"]["node"] = "N18"
    with pytest.raises(ValueError, match="antenna.node"):
        spacecraft.open_loop(0.03, params=p)
    ol = spacecraft.open_loop(0.02, theta=1.0, uncertain=True)
    assert ol.parameters["theta"] is None and ol.parameters["hub_mass"] is None and ol.parameters["h"] == 0.02


# ---------------------------------------------------------------- mutation-testing additions (review of 2026-12-03)
def test_pma_force_to_wrench_is_the_reaction_of_its_spring_mass_damper():
    """Base held (a_P = 0): the proof mass obeys m x'' = u - k x - d x', so X / U = 1 / (m s^2 + d s + k) and the wrench
    on the parent is the reaction -m x'' v applied at G: W_P / U = -[v; r_PG x v] m s^2 / (m s^2 + d s + k),
    in the parent frame (rotation R) as R6 times that."""
    pm = PARAMS["pma"]
    m, k, d = pm["proof_mass"], pm["stiffness"], pm["damping"]
    v = np.array([1.0, 0.0, 0.0])  # off the CoG offset (0, 0.05, 0): a non-zero moment at P
    rot = frames.rot_z(0.4) @ frames.rot_x(-0.7)
    model = bodies.pma("N", [0.2, -0.1, 0.3], rot, pm["casing_mass"], pm["casing_inertia"], pm["r_og"], m, k, d, axis=v)
    w = np.array([0.5, 3.0, np.sqrt(k / m), 30.0])
    g = model.freqresp(w)
    u, node = model.channels("pma")[0], model.channels("N")
    s = 1j * w
    x_u = 1.0 / (m * s**2 + d * s + k)
    r_pg = np.asarray(pm["r_og"]) - np.asarray(pm["r_op"])
    dirs = np.r_[rot @ v, rot @ np.cross(r_pg, v)]
    np.testing.assert_allclose(g[u, u], x_u, rtol=1e-10)
    np.testing.assert_allclose(g[node, u], -np.outer(dirs, m * s**2 * x_u), rtol=1e-10, atol=1e-12)


def test_sadm_joint_of_a_panel_with_uncoupled_modes_is_a_rigid_body_on_a_spring_damper():
    """Zero participation factors leave a rigid panel on the joint: J theta'' = -(k theta + f theta') + p with J the
    inertia about the joint axis at the joint, from the parallel-axis theorem J = e^T (J_G + m (|r|^2 I - r r^T)) e."""
    sp, ch = PARAMS["solar_panel"], PARAMS["choices"]
    m, r, j_g = sp["mass"], np.asarray(sp["r_og"]), np.asarray(sp["inertia_g"])
    e = np.array([0.6, 0.0, 0.8])
    k, f = ch["sadm_stiffness"], ch["sadm_friction"]
    panel = bodies.solar_panel("P6", [0.0, 0.0, 0.0], np.eye(3), m, r, j_g, sp["omega"], sp["damping"], np.zeros((3, 6)),
                               e, k, f, label="SP1")
    j_e = e @ (j_g + m * (r @ r * np.eye(3) - np.outer(r, r))) @ e
    w = np.array([0.5, np.sqrt(k / j_e), 20.0])
    s = panel.channels("SP1")[0]
    np.testing.assert_allclose(panel.freqresp(w)[s, s], 1.0 / (-j_e * w**2 + 1j * f * w + k), rtol=1e-9)


def test_a_preset_sets_the_parameters_it_names_and_nothing_else(tmp_path, monkeypatch):
    """A preset's loop settings, choices and model inputs reach the parameters (and so their fingerprint, which keys
    every stored result); an entry the parameters do not have is refused, naming it."""
    import json

    from trusscodesign.control.closedloop import LoopSettings
    from trusscodesign.infra import paths

    base = spacecraft.load_parameters()
    p = spacecraft.preset_parameters("paper_calibrated")
    preset = spacecraft.load_preset("paper_calibrated")
    s = LoopSettings.from_parameters(p)
    for k, v in preset["closed_loop"].items():
        if not k.startswith("_"):
            assert getattr(s, k) == v
    model = preset["model"]
    assert p["antenna"]["node"] == model["antenna_node"] and p["truss"]["damping"] == model["truss_damping"]
    assert p["truss"]["damping_model"] == model["truss_damping_model"]
    assert spacecraft.parameters_fingerprint(p) != spacecraft.parameters_fingerprint(base)
    assert base == spacecraft.load_parameters()  # the package's parameters are not edited
    untouched = {k: v for k, v in base["closed_loop"].items() if k not in preset["closed_loop"]}
    assert all(p["closed_loop"][k] == v for k, v in untouched.items()) and p["hub"] == base["hub"]
    folder = tmp_path / "spacecraft" / "presets"
    folder.mkdir(parents=True)
    (folder / "bad.json").write_text(json.dumps({"closed_loop": {"u_maximum": 1.0}}))
    (folder / "bad_model.json").write_text(json.dumps({"model": {"antenna": "N17"}}))
    (folder / "bad_value.json").write_text(json.dumps({"model": {"truss_damping": "1e-4", "_why": "a text"}}))
    monkeypatch.setattr(paths, "PACKAGE_DATA", tmp_path)
    with pytest.raises(ValueError, match=r"preset 'bad': unknown closed_loop entries \['u_maximum'\]; allowed: .*'u_max'"):
        spacecraft.preset_parameters("bad", base)
    with pytest.raises(ValueError, match=r"preset 'bad_model': unknown model entries \['antenna'\]; allowed: .*'antenna_node'"):
        spacecraft.preset_parameters("bad_model", base)
    with pytest.raises(TypeError, match="truss_damping must be a real number"):  # named, not called an unknown entry
        spacecraft.preset_parameters("bad_value", base)


def test_model_inputs_leave_out_the_loop_settings_only():
    p = spacecraft.load_parameters()
    loop = spacecraft.with_choices(p) | {"closed_loop": {**p["closed_loop"], "u_max": 1.0},
                                         "choices": {**p["choices"], "xi_pma": 0.3, "effort": "transmitted"}}
    assert spacecraft.model_inputs(loop) == spacecraft.model_inputs(p)
    assert spacecraft.model_inputs(spacecraft.with_choices(p, antenna_node="N17")) != spacecraft.model_inputs(p)


def test_study_parameters_are_the_stated_values_or_a_presets():
    assert spacecraft.study_parameters("stated") == spacecraft.load_parameters()
    assert spacecraft.study_parameters("paper_calibrated") == spacecraft.preset_parameters("paper_calibrated")
    with pytest.raises(ValueError, match="unknown preset 'calibrated'.*or 'stated' for the paper's stated values"):
        spacecraft.study_parameters("calibrated")


def test_the_readings_of_the_disturbance_and_of_the_pma_layout() -> None:
    """disturbance="hub": the SADM torque inputs of G are the hub's torque about x at P1 (both columns); a named PMA layout
    sets choices.pma_layout; a bad name is refused naming the allowed ones."""
    base = spacecraft.load_parameters()
    g = spacecraft.open_loop(0.02139, theta=0.3, params=spacecraft.with_choices(base, disturbance="hub")).G
    hub = spacecraft.INPUTS.index("W_P1_Rx")
    for name in ("p_SP1", "p_SP2"):
        j = spacecraft.INPUTS.index(name)
        assert np.array_equal(g.B[:, j], g.B[:, hub]) and np.array_equal(g.D[:, j], g.D[:, hub])
    g0 = spacecraft.open_loop(0.02139, theta=0.3, params=base).G
    assert not np.allclose(g0.B[:, 0], g0.B[:, hub])
    p = spacecraft.with_choices(base, pma_layout="all at N17", pma_r_og=[0.0, 0.0, 0.0])
    assert [x["node"] for x in p["choices"]["pma_layout"]] == ["N17"] * 4 and p["pma"]["r_og"] == [0.0, 0.0, 0.0]
    assert spacecraft.with_choices(base, pma_layout="couples")["choices"]["pma_layout"] == base["choices"]["pma_layout"]
    with pytest.raises(ValueError, match=r"disturbance must be one of \['sadm', 'hub'\]"):
        spacecraft.with_choices(base, disturbance="panel")
    with pytest.raises(ValueError, match="pma_layout must be one of"):
        spacecraft.with_choices(base, pma_layout="N17")


@pytest.mark.parametrize("kwargs, match", [(dict(h=3.0), "cm or mm"), (dict(h=21.39), "cm or mm"), (dict(theta=90.0), "degrees")])
def test_open_loop_refuses_cm_and_degrees_before_building(kwargs, match):
    with pytest.raises(ValueError, match=match):  # was built: a truss of 3 m beams in 4 s, 1.8e6 kg
        spacecraft.open_loop(**kwargs)
    with pytest.raises(ValueError, match="cm or mm"):
        spacecraft.truss_mass(3.0)
    assert spacecraft.truss_mass(0.03) == pytest.approx(183.11, rel=1e-3)


@pytest.mark.parametrize("value, match", [(3.0, r"h_fe\[1\] must be a section side in metres in \(0, 0.1\].*cm or mm"),
                                          ("2cm", r"h_fe\[1\] \[m\] must be a real number, got str"),
                                          (0.0, r"h_fe\[1\] \[m\] must be a finite positive number")])
def test_a_section_side_names_the_parameter_its_unit_and_range(value, match):
    """Notebook 04's sides (h = 3, cm typed as m, gave an empty AssertionError on the slow-pole count)."""
    with pytest.raises((TypeError, ValueError), match=match):
        spacecraft.check_section_side(value, name="h_fe[1]")
    assert spacecraft.check_section_side(0.02139) == 0.02139


@pytest.mark.parametrize("hub_mass, error", [(-5.0, ValueError), (np.nan, ValueError), ("800", TypeError)])
def test_component_masses_checks_hub_mass(hub_mass, error):
    with pytest.raises(error, match="hub_mass"):  # was returned as given
        spacecraft.component_masses(0.03, hub_mass=hub_mass)
    assert spacecraft.component_masses(0.03, hub_mass=900)["hub"] == 900


@pytest.mark.parametrize("name", ["../parameters", "../presets/paper_match"])
def test_load_preset_takes_names_of_presets_only(name):
    with pytest.raises(ValueError, match=r"unknown preset.*available: \['paper_calibrated', 'paper_match'\]"):  # ../parameters was returned
        spacecraft.load_preset(name)
    assert "closed_loop" in spacecraft.load_preset("paper_match")


def _rel_err(g1, g0):
    return np.max(np.max(np.abs(g1 - g0), axis=(0, 1)) / np.max(np.abs(g0), axis=(0, 1)))


def test_uncertain_tunable_spacecraft_equals_direct_build():
    ol = spacecraft.open_loop(uncertain=True, tunable=True)
    occ = ol.lft.occurrences()
    assert occ == {"M_SC": 3, "Iyy_SC": 1, "omega1_SP": 4, "tau": 32, "h": 1112}
    vals = {"h": 0.015, "M_SC": 960.0, "Iyy_SC": 800.0, "omega1_SP": 2.008, "tau": -1.0}  # a corner
    a, b, c, d = ol.lft.evaluate(vals)
    ref = spacecraft.open_loop(vals["h"], theta=4 * np.arctan(vals["tau"]), hub_mass=vals["M_SC"], hub_iyy=vals["Iyy_SC"],
                               panel_omega1=vals["omega1_SP"]).G
    s1, s2 = reduction.split_slow(a, b, c, d), reduction.split_slow(ref.A, ref.B, ref.C, ref.D)
    w = np.logspace(-3, 4, 120)
    assert _rel_err(statespace.modal_frequency_response(*s1.fast, w), statespace.modal_frequency_response(*s2.fast, w)) < 1e-8


def test_the_parameters_fingerprint_follows_values_not_notes():
    from trusscodesign.model import spacecraft

    base = spacecraft.load_parameters()
    edited = json.loads(json.dumps(base))
    edited["hub"]["mass"] = 400.0  # a value: another fingerprint
    noted = json.loads(json.dumps(base))
    noted["_provenance"] = "another note"  # a note: the same
    assert spacecraft.parameters_fingerprint(edited) != spacecraft.parameters_fingerprint() == spacecraft.parameters_fingerprint(noted)


def test_section_sides_by_member_group():
    """One side for all, given by group, is the paper's truss (assembled member by member): the reduced model (slow
    spurious poles removed) equal to 1e-9; the mass by group is the closed form; h stays a number for tunable models."""
    from trusscodesign.model.statespace import frequency_response

    by_group = spacecraft.open_loop({"all": 0.02139})
    paper = spacecraft.open_loop(0.02139)
    assert by_group.parameters["h"] is None and by_group.parameters["h_all"] == 0.02139
    red = [reduction.modal_reduction(m.G.A, m.G.B, m.G.C, m.G.D).reduced for m in (by_group, paper)]
    w = [0.0, 10.0, 97.7, 400.0]
    g1, g2 = (frequency_response(*r, w) for r in red)
    assert red[0][0].shape == red[1][0].shape == (784, 784) and np.max(np.abs(g1 - g2)) < 1e-9 * np.max(np.abs(g2))
    # 20 m of longerons, 20 m of battens, 25 diagonals of sqrt(2) m
    sides = {"longerons": 0.03, "all": 0.02}
    assert np.isclose(spacecraft.truss_mass(sides), 2700.0 * (0.03**2 * 20 + 0.02**2 * (20 + 25 * np.sqrt(2))), rtol=1e-13)
    with pytest.raises(ValueError, match="tunable scales one section side h"):
        spacecraft.open_loop(sides, tunable=True)
    with pytest.raises(ValueError, match=r"section keys \['spars'\] name no cube or group"):
        spacecraft.open_loop({"spars": 0.02, "all": 0.02})
    with pytest.raises(ValueError, match=r"sides\['all'\] must be a section side in metres"):
        spacecraft.truss_mass({"all": 2.0})
