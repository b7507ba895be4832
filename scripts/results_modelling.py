"""The results page's sections on the modelling: notebooks 01 to 05 (``scripts/results_page.py``)."""

from __future__ import annotations


from results_format import cm, pct, sci, table


def nb01(d: dict) -> str:
    p, r = d["01"]["parameters"], d["01"]["results"]
    e, conv = r["clamped_free_relative_errors"], r["convergence"]
    rows = [[mode] + [sci(x, 2) for x in errs] for mode, errs in conv["relative_errors"].items()]
    polar, exact = r["torsion_frequency_polar_vs_exact_rad_s"]
    return f"""## 01 · The TITOP beam

An aluminium beam of length {p['length']:g} m and square section of side {cm(p['h'])} cm, as an analytical
Euler-Bernoulli TITOP model of order {r['model_order']}. Clamped at one end and free at the other, its first two bending
frequencies are {pct(e['bending_y_1'], 3, True)} and {pct(e['bending_y_2'], 2, True)} from the closed form, the
axial and torsion ones {pct(e['axial_1'], 2, True)}. Its statics are exact: the tip compliance to
{sci(r['static_compliance_max_relative_error'])} and the rigid mass (the DC gain) to
{sci(r['dc_mass_max_relative_error'])} relative. The other boundary conditions come from channel inversion of the
same model: clamped-clamped, the first bending frequency is exact to {sci(r['clamped_clamped_bending1_relative_error'])}
(with {r['poles_at_zero_after_cc_inversion']} poles at zero from the inverted channels); pinned-pinned, it is
{pct(r['pinned_pinned_bending1_relative_error'], 4, True)} off; inverting twice gives back the model to
{sci(r['double_inversion_max_relative_error'])}.

Convergence of the frequencies with the order of the model (richer Ritz basis), relative error against the closed
form:

{table(['mode'] + [f'order {n}' for n in conv['orders']], rows)}

The order-{conv['orders'][0]} model has no third bending mode worth the name (error
{pct(conv['relative_errors']['bending_y 3'][0], 1)}); every other error falls with the order. With the polar moment
as torsion constant (the SDT convention the paper follows) the torsion frequency is {polar:.1f} rad/s against
{exact:.1f} rad/s with the true torsion constant of a square section ({pct(polar / exact - 1, 1, True)}).
"""


def nb02(d: dict) -> str:
    p, r = d["02"]["parameters"], d["02"]["results"]
    fc = r["fe_convergence"]
    names = {"L_CFC": "L-chain `L^CFC`", "T_CFF": "triangle `T^CFF`", "S_CFFF": "square `S^CFFF`"}
    rows = []
    for key, label in names.items():
        m = r[key]
        mass = sci(m["rigid_mass_relative_error"]) if "rigid_mass_relative_error" in m else "-"
        rows.append([label, sci(m["max_direct_error"]), mass, str(m["poles_at_zero"])]
                    + [pct(x, 3) for x in fc["max_error_first6"][key]])
    head = ["mechanism", "block diagram vs direct assembly", "rigid mass", "poles at zero"] + [
        f"FE, first 6 modes, {n} mode{'s' if n > 1 else ''} per field" for n in fc["n_modes"]]
    l_fe = r["L_CFC"]["fe_errors"]
    bad = [i + 1 for i, x in enumerate(l_fe) if abs(x) > 0.1]
    return f"""## 02 · Two-dimensional mechanisms

The L-chain, the triangle and the squares of {p['side']:g} m beams (h = {cm(p['h'])} cm), built by feedback
interconnection of TITOP beams and channel inversion, against a direct constrained assembly of the same beams and a
frame finite-element model ({p['fe_elements']} elements per member), relative errors of the frequencies:

{table(head, rows)}

The block diagrams equal the direct assembly to round-off. Against the frame FE model, the triangle and the square
are within {pct(max(fc['max_error_first6']['T_CFF'][0], fc['max_error_first6']['S_CFFF'][0]), 2)} on their first six
modes with the default beams. The L-chain clamped at both ends is the exception: its modes from the
{bad[0]}th on have no counterpart in the default beams (errors up to {pct(max(l_fe), 0)}); one more mode per field
brings the first six to {pct(fc['max_error_first6']['L_CFC'][1], 2)}. Clamped at every node, the inverted
models keep their rigid-body poles at zero: {r['L_CCC']['poles_at_zero']} for `L^CCC`, {r['S_CCCC']['poles_at_zero']} for `S^CCCC`. The rigid mass
of `L^FFC`, from its DC gain, is exact to {sci(r['L_FFC']['rigid_mass_relative_error'])}.
"""


def nb03(d: dict) -> str:
    r = d["03"]["results"]
    f, err = r["frequencies_rad_s"], r["mean_relative_error_vs_nastran"]
    cols = [("nastran", "Nastran (paper)"), ("paper_sdt", "SDT (paper)"), ("this_sdt_settings", "this, SDT settings"),
            ("this_exact_J", "this, true torsion constant"), ("opensees_same_choices", "OpenSees, SDT settings")]
    rows = [[str(i + 1)] + [f"{f[k][i]:.2f}" for k, _ in cols] for i in range(len(f["nastran"]))]
    gap = r["gap_study_mean_error_vs_nastran"]
    gap_rows = []
    for key, value in gap.items():
        torsion, mass, elements = key.split("|")
        gap_rows.append([{"polar": "polar moment", "exact": "true"}[torsion], mass, elements, pct(value, 2)])
    best = r["gap_best_choice"]
    lay = [[x["side"], x["top"], f"{x['freq_mean_err_vs_SDT_pct']:.2f} %", f"{x['freq_mean_err_vs_Nastran_pct']:.2f} %",
            f"{x['max_factor_dev_vs_SDT']:.3f}", f"{x['max_factor_dev_vs_Nastran']:.3f}"] for x in r["layouts"]]
    return f"""## 03 · The cube against the paper's Nastran and SDT data

The cube `C^{{CFFF-FFFF}}` (clamped at N1), first {len(f['nastran'])} frequencies in rad/s:

{table(['mode'] + [c for _, c in cols], rows)}

With the paper's SDT settings (the polar moment as torsion constant, order-20 beams) the model reproduces the paper's
SDT column to {pct(r['max_relative_error_vs_paper_sdt'], 2)} at worst, and sits above Nastran by
{pct(err['this_sdt_settings'], 2)} on average (the paper's SDT: {pct(err['paper_sdt'], 2)}; largest
{pct(r['max_relative_error_vs_nastran'], 1)}). With the true torsion constant the mean error against Nastran is
{pct(err['this_exact_J'], 2)}. The participation factors are within {r['max_factor_deviation_vs_sdt']:.4f} of the SDT
column; the effective masses are {min(r['effective_mass_ratio_vs_nastran']):.3f}-{max(r['effective_mass_ratio_vs_nastran']):.3f}
times Nastran's. The cube's mass from the DC gain, {r['total_mass_kg']:.2f} kg, equals its rigid mass to
{sci(r['dc_gain_vs_rigid_mass_relative_error'])}.

The paper's figure does not say which diagonals the cube's faces carry. Of the four layouts compared, one
matches the SDT column (frequencies and factors); the others swap modes or factors:

{table(['side diagonals', 'top diagonal', 'frequencies vs SDT (mean)', 'vs Nastran (mean)', 'factors vs SDT (largest deviation)', 'vs Nastran'], lay)}

**The SDT-Nastran gap, explained** with a real finite-element engine (OpenSeesPy; with the SDT settings it agrees with
this model to {pct(max(abs(a / b - 1) for a, b in zip(f['opensees_same_choices'], f['this_sdt_settings'], strict=True)), 2)}),
one modelling choice at a time, mean error against Nastran:

{table(['torsion constant', 'mass matrix', 'elements per member', 'mean error vs Nastran'], gap_rows)}

The {best['torsion']} torsion constant, a {best['mass']} mass matrix (Nastran's default) and {best['elements']}
elements per member (the paper's mesh) reproduce the Nastran frequencies to {pct(best['mean_error'], 2)} on average
({pct(best['max_error'], 2)} at worst): the gap is the torsion constant and the mass matrix, not the sub-structuring.
That FE model's participation factors are within {r['max_factor_deviation_fe_nastran_like_vs_nastran_excluding_mode5_T1']:.4f}
of Nastran's, leaving out the mode-5 T1 entry, whose printed sign no model reproduces (a sign typo of the table, shown
in the notebook).
"""


def nb04(d: dict) -> str:
    r, p, p7 = d["04"]["results"], d["04"]["parameters"], d["07"]["results"]["paper"]
    o = r["orders"]
    mass_rows = [[f"{m['h_cm']:g}", f"{m['mass_dc_kg']:.2f}", sci(abs(m["rel_error"])), f"{m['truss_from_dc_kg']:.3f}",
                  f"{m['truss_rho_h2_l_kg']:.3f}"] for m in r["masses"]]
    n_fe = len(next(iter(r["fe_frequencies"].values()))["titop"])
    return f"""## 04 · The T-truss and the spacecraft

The T-truss (five cubes) by sub-structuring, against OpenSees with the same beams, clamped at its four interface
nodes: the first {n_fe} frequencies agree to {pct(r['fe_max_relative_error'], 3)} at h =
{' / '.join(cm(float(h)) for h in r['fe_frequencies'])} cm.

The open-loop spacecraft model G (hub, truss, four proof-mass actuators, two solar panels on their drive mechanisms,
antenna) has order {o['G']} (truss {o['truss']}, PMAs {o['pmas']}, panels the rest), {o['inputs']} inputs and
{o['outputs']} outputs. Closing the loops by channel inversion leaves {r['near_zero_poles']} spurious poles near zero,
as in the paper; their contribution to the input-output behaviour is {sci(r['slow_pole_contribution'])}, and they are
removed (notebook 05). The masses from the DC gain equal the sums of the components:

{table(['h [cm]', 'spacecraft mass [kg]', 'relative difference to the sum', 'truss mass from the DC gain [kg]', 'truss rho h^2 L [kg]'], mass_rows)}

At h = {cm(p['h'])} cm the truss weighs {r['truss_mass_h3cm_kg']:.3f} kg: the paper's m0 is {p7['m0_kg']} kg. The
largest singular value of G is {r['max_singular_value_db']:.1f} dB.
{damping(r["damping"])}"""


def nb04b(d: dict) -> str:
    p, r = d["04b"]["parameters"], d["04b"]["results"]
    b, pl = r["boom"], r["plate"]
    v_rows = [[v["truss"], str(v["members"]), f"{v['first [Hz]']:.3f}", sci(v["largest gap"])] for v in r["validation"]]
    d_rows = [[str(x["cubes"]), str(x["order"]), str(x["spurious poles"]), sci(x["largest gap"])] for x in r["dense"]]
    ex = {k: v["p"] for k, v in r["exponents"].items() if v is not None}
    return f"""## 04b · Any truss built from cubes

A boom of {b['cubes']} cubes ({b['members']} members) with longerons of {cm(p['longeron_h'])} cm and the other members at
{cm(p['h'])} cm weighs {b['mass_kg']:.1f} kg ({b['mass_uniform_kg']:.1f} kg with one section for all); its first
frequency is {b['frequencies_hz'][0]:.3f} Hz ({b['frequencies_uniform_hz'][0]:.3f} Hz). The T-truss rebuilt from five cube
placements has the poles of notebook 04's block diagram to {sci(r['t_truss_gap'])}. A plate of {pl['size'][0]} x {pl['size'][1]}
cubes ({pl['members']} members, {pl['mass_kg']:.1f} kg at {cm(p['h'])} cm) clamped at the base of its middle cube has its first
frequency at {pl['frequencies_hz'][0]:.3f} Hz.

The paper's block diagram and the sparse constrained assembly of the same beams (no spurious poles), booms clamped at
their base, largest relative gap of the first {p['n_compare']} frequencies:

{table(['cubes', 'order', 'spurious poles', 'largest gap'], d_rows)}

Against OpenSeesPy ({p['fe_elements']} elements per member), the first {p['n_compare']} frequencies with
{p['validation_n_modes']} Ritz modes per field (bar {sci(p['tolerance'])}):

{table(['truss', 'members', 'first frequency [Hz]', 'largest gap'], v_rows)}

Wall time against the number of cubes, exponent p of time ~ cubes^p fitted over the booms of 5 cubes and more (this
run, on its machine; the benchmark `benchmarks/truss_scaling.py` measures the same on an idle one):
{'; '.join(f'{k} {v:.2f}' for k, v in ex.items())}.
"""


def damping(dm: dict) -> str:
    """Notebook 04's damping study (docs/titop.md, section g)."""
    beam = {(b["model"], b["clamped at"], b["mode"]): b["zeta"] for b in dm["beam"]}
    rows = [[t["model"], t["assembly"], ", ".join(f"{z:g}" for z in t["zeta_1-3 [1e-4]"]),
             f"{t['zeta / as built, 20 modes (min)']:.3f}-{t['(max)']:.3f}"] for t in dm["truss"]]
    freqs = ", ".join(f"{w:g}" for w in dm["truss"][0]["omega_1-3 [rad/s]"])
    bd = dm["block_diagram_vs_constrained"]
    passive = [[r["truss damping"], f"{r['J_c passive']:.4f}", f"{r['critical omega [rad/s]']:.2f}",
                f"{r['critical panel angle [deg]']:.1f}"] for r in dm["passive"]]
    return f"""
**Damping and the beams' orientation** (docs/titop.md, section g). A 1 m cantilever at h = {cm(dm['h'])} cm with the
paper's damping (ratio xi on the modes clamped at P) has ratios {beam[('clamped_modes', 'P', 1)]:.3g} on its first three
modes clamped at P, and {', '.join(f"{beam[('clamped_modes', 'C', k)]:.3g}" for k in (1, 2, 3))} clamped at C; with
stiffness-proportional damping, {', '.join(f"{beam[('stiffness', 'C', k)]:.3g}" for k in (1, 2, 3))} either way. The
T-truss carrying the antenna, clamped at its base (modes at {freqs} rad/s), assembled by constraints with its beams
reversed at random and in random orders (the block diagram's own orientations agree with the block diagram to
{sci(bd['max_rel_freq_diff'])} in frequency and {sci(bd['max_rel_zeta_diff'])} in damping):

{table(['damping model', 'assembly', 'first three ratios [1e-4]', 'ratio to as built, first 20 modes'], rows)}

The passive loop (ACS closed, PMAs off) at the same h, worst case over the uncertainty box:

{table(['truss damping', 'J_c passive', 'critical frequency [rad/s]', 'critical panel angle [deg]'], passive)}
"""


def nb05(d: dict) -> str:
    r, p = d["05"]["results"], d["05"]["parameters"]
    occ, occ_p = r["occurrences"], r["paper_occurrences"]
    names = ("M_SC", "Iyy_SC", "omega1_SP", "tau", "h")
    ex = r["exactness"]
    red = [[f"{x['h_cm']:g}", str(x["order_G"]), str(x["slow_removed"]), str(x["order_G_r_low"]), str(x["order_G_r"]),
            sci(abs(x["mass_rel_change"]))] for x in r["reduction"]]
    g_r_2cm = next(x["order_G_r"] for x in r["reduction"] if x["h_cm"] == 2.0)
    moves = ", ".join(f"{k} {sci(v)}" for k, v in ex["reference_one_ulp_moves"].items())
    below = r["G_r_error_below_band"]
    return f"""## 05 · Uncertain model and reduction

The uncertain and tunable parameters enter as an LFT `F_u(G, Delta)`; how often each is repeated in Delta:

{table(['parameter', 'paper', 'here'], [[n, str(occ_p[n]), str(occ[n])] for n in names])}

The hub mass and inertia and the panel frequency occur as often as in the paper. The panel angle tau occurs
{occ['tau']} times, {r['tau_hankel_rank_per_panel']} per panel, the least an exact two-sided rotation needs (the rank
of a Hankel matrix, computed in the notebook); the section side h occurs {occ['h']} times against {occ_p['h']}, from
the beams' h-dependent blocks and the port conversions of the truss.

Exactness: at {ex['n_draws']} draws of the parameters (box corners included), `F_u(G, Delta)` equals the model built
directly at those values to {sci(ex['median_relative_error'])} (median) and {sci(ex['max_relative_error'])} at worst,
over {p['n_grid']} frequencies plus points at every peak. The worst draw sits near a very lightly damped mode, where the
direct build is itself no more accurate: moving one of its inputs by one unit in the last place changes its response
by up to {sci(ex['reference_one_ulp_resolution'])} ({moves}). Matched one to one, the poles of the two routes differ by
{sci(ex['pole_rel_error_max'])} relative at worst.

Reduction: the spurious slow poles are removed (`G_r_low`, all flexible modes), then the modes above
{p['omega_high']:g} rad/s are residualised (`G_r`, the synthesis model):

{table(['h [cm]', 'order of G', 'slow poles removed', 'G_r_low', 'G_r', 'mass change'], red)}

At 2 cm `G_r` has {g_r_2cm} states, the paper's count. `G` and `G_r_low` have the same peak response to
{sci(r['G_minus_G_r_low_peak_ratio'])}; below {p['omega_band']:g} rad/s `G_r` departs from `G_r_low` by
{sci(below['disturbance -> LOS'])} (disturbance to line of sight) and {sci(below['PMA force -> measurements'])}
(PMA forces to measurements).
"""
