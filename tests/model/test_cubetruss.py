"""Trusses built from cubes: the T-truss as one instance (equal to the cube-by-cube block diagram), booms and plates
against the constrained assembly and OpenSeesPy, per-group sections, invariance to the boom's axis, and the refusals."""

from __future__ import annotations

import numpy as np
import pytest
from trusscodesign.model import assembly, cubetruss, opensees_fe, titop, truss
from trusscodesign.model.cubetruss import Cube
from trusscodesign.model.lft import Parameter

SEC = titop.Section.square(0.02139)
BASE = ["N1", "N2", "N3", "N4"]


def _frequencies(model) -> np.ndarray:
    """Natural frequencies [rad/s] of the flexible modes (the loop closures' spurious poles near s = 0 left out)."""
    p = np.linalg.eigvals(model.a)
    return np.sort(np.abs(p[(p.imag > 0) & (np.abs(p) > 1e-2)]))


def test_the_t_truss_of_cubes_is_the_papers_block_diagram():
    """Nodes, members and mass as today's; the member-by-member model has the poles (1e-9) and the frequency response
    (1e-8, away from the spurious poles near s = 0) of the cube-by-cube one."""
    t = truss.t_truss_cubes()
    nodes = truss.truss_nodes()
    assert list(t.nodes) == list(nodes) and all(np.allclose(t.nodes[n], nodes[n], atol=1e-15) for n in nodes)
    assert t.pairs() == truss.truss_members()
    # five cubes of eight 1 m edges and five diagonals: 40 + 25 sqrt(2) m of members (m0 = 183.11 kg at h = 3 cm)
    assert np.isclose(t.mass(SEC), SEC.density * SEC.area * (40 + 25 * np.sqrt(2)), rtol=1e-13)
    assert round(t.mass(titop.Section.square(0.03)), 2) == 183.11
    general = cubetruss.truss_model(t, SEC, BASE, ["N17", "N20"])
    paper = truss.t_truss(SEC)
    assert general.port_names == paper.port_names and general.nstates == paper.nstates == 1300
    f1, f2 = _frequencies(general), _frequencies(paper)
    assert f1.size == f2.size == 380 and np.max(np.abs(f1 / f2 - 1)) < 1e-9
    w = np.array([10.0, 97.7, 400.0])
    g1, g2 = general.freqresp(w), paper.freqresp(w)
    assert np.max(np.abs(g1 - g2)) < 1e-8 * np.max(np.abs(g2))


@pytest.mark.parametrize("n", [1, 2, 3])
def test_booms_match_the_constrained_assembly_and_opensees(n):
    """Every flexible mode against the Lagrangian assembly of the same beams (1e-9); the first 20 against OpenSeesPy
    frame elements within the T-truss's bar (5e-3). A one-cube boom's first 20 modes reach its members' own bending,
    which needs two Ritz modes per field (with one: 1.2 % on its 19th mode)."""
    boom = cubetruss.boom(n)
    assert len(boom.members) == 13 * n and len(boom.nodes) == 4 * (n + 1)
    n_modes = 2 if n == 1 else 1
    f = _frequencies(cubetruss.truss_model(boom, SEC, BASE, n_modes=n_modes))
    ref = np.sort(np.abs(assembly.constrained_poles(boom.nodes, boom.pairs(), SEC, BASE, n_modes)))
    assert f.size == ref.size and np.max(np.abs(f / ref - 1)) < 1e-9
    fe = opensees_fe.frame_frequencies(boom.nodes, boom.pairs(), SEC, BASE, 10, "consistent", 20)
    assert np.max(np.abs(f[:20] / fe - 1)) < 5e-3


def test_a_plate_builds_shared_members_once_and_matches_both_references():
    """2 x 2 cubes: 18 nodes; 9 longerons, 12 battens, 4 top and 12 side diagonals (the checkerboard of layouts gives a
    shared face one diagonal); clamped at one cube's base."""
    plate = cubetruss.plate(2, 2)
    assert len(plate.nodes) == 18
    groups = [m.group for m in plate.members]
    assert (groups.count("longerons"), groups.count("battens"), groups.count("diagonals")) == (9, 12, 16)
    clamped = [plate.cube_nodes["C1_1"][k] for k in BASE]
    f = _frequencies(cubetruss.truss_model(plate, SEC, clamped))
    ref = np.sort(np.abs(assembly.constrained_poles(plate.nodes, plate.pairs(), SEC, clamped)))
    assert f.size == ref.size and np.max(np.abs(f / ref - 1)) < 1e-9
    fe = opensees_fe.frame_frequencies(plate.nodes, plate.pairs(), SEC, clamped, 10, "consistent", 20)
    assert np.max(np.abs(f[:20] / fe - 1)) < 5e-3


def test_a_plate_clamped_at_one_corner_node_frees_and_clamps_by_inversion():
    """Clamped at a single node that a member carries (N5, a top corner), with ports at two nodes that no member
    carries (bottom corners, freed by inversion): the poles of the constrained assembly."""
    plate = cubetruss.plate(2, 2)
    model = cubetruss.truss_model(plate, SEC, ["N5"], ["N1", "N2"])
    f = _frequencies(model)
    ref = np.sort(np.abs(assembly.constrained_poles(plate.nodes, plate.pairs(), SEC, ["N5"])))
    assert f.size == ref.size and np.max(np.abs(f / ref - 1)) < 1e-8


def test_nodes_are_merged_by_distance_and_crossing_diagonals_refused():
    """Eight flat cubes stacked at 0.321 m: 7 x 0.321 and 6 x 0.321 + 0.321 differ in the last bit and straddled a
    rounding grid (the truss came out with 40 nodes instead of 36, and rigid modes); two cubes side by side with the
    same side layout cross their diagonals on the shared face."""
    flat = [Cube(f"C{k}", (0.0, 0.0, k * 0.321), sides=(0.64, 0.64, 0.321)) for k in range(8)]
    stack = cubetruss.cube_truss(flat)
    assert len(stack.nodes) == 36
    assert stack.modes(SEC, ["N1", "N2", "N3", "N4"], k=2).frequencies[0] > 1.0
    with pytest.raises(ValueError, match="crosses member .* of cube A at their midpoint"):
        cubetruss.cube_truss([Cube("A", (0, 0, 0)), Cube("B", (1, 0, 0))])
    assert len(cubetruss.cube_truss([Cube("A", (0, 0, 0)), Cube("B", (1, 0, 0), side="backward")]).members) == 26 - 4


def test_carriers_in_a_loop_are_refused():
    """A hand-made description whose members carry their nodes round a loop (an algebraic loop in the block
    diagram)."""
    base = cubetruss.boom(1)
    members = [cubetruss.Member("N5", "N6", "battens", "C1"), cubetruss.Member("N6", "N7", "battens", "C1"),
               cubetruss.Member("N7", "N5", "battens", "C1")]
    looped = cubetruss.CubeTruss(base.cubes, base.nodes, members + base.members, base.cube_nodes)
    with pytest.raises(ValueError, match="form a loop"):
        cubetruss.truss_model(looped, SEC, BASE)


def test_the_boom_does_not_depend_on_its_axis():
    f = [_frequencies(cubetruss.truss_model(cubetruss.boom(2, 0.8, axis), SEC, BASE)) for axis in ("x", "y", "z")]
    assert np.max(np.abs(f[0] / f[2] - 1)) < 1e-9 and np.max(np.abs(f[1] / f[2] - 1)) < 1e-9


def test_any_clamped_nodes_and_ports():
    """A boom hanging from its top face, its base a port: the nodes carried by a member are clamped and those carried
    by none freed, by channel inversion; the poles are the constrained assembly's."""
    boom = cubetruss.boom(2)
    top = ["N9", "N10", "N11", "N12"]
    model = cubetruss.truss_model(boom, SEC, top, ["N1"])
    assert model.port_names == top + ["N1"]
    ref = np.sort(np.abs(assembly.constrained_poles(boom.nodes, boom.pairs(), SEC, top)))
    f = _frequencies(model)
    assert f.size == ref.size and np.max(np.abs(f / ref - 1)) < 1e-9


def test_sections_per_group_and_per_cube():
    """One section for all, however given, is the same model; stiffer longerons raise the first frequency (measured:
    by 5.5 %, their mass rising too) and the mass by what their sections add; the per-member sections agree with both
    references."""
    boom = cubetruss.boom(3)
    one = _frequencies(cubetruss.truss_model(boom, SEC, BASE))
    assert np.array_equal(one, _frequencies(cubetruss.truss_model(boom, {"all": SEC}, BASE)))
    stiff = titop.Section.square(0.03)
    sections = {"longerons": stiff, "all": SEC}
    per_member = boom.sections(sections)
    assert [s is stiff for s in per_member] == [m.group == "longerons" for m in boom.members]
    f = _frequencies(cubetruss.truss_model(boom, sections, BASE))
    assert f[0] > 1.03 * one[0]
    longerons = sum(boom.length(m) for m in boom.members if m.group == "longerons")
    assert np.isclose(boom.mass(sections) - boom.mass(SEC), SEC.density * (stiff.area - SEC.area) * longerons, rtol=1e-12)
    ref = np.sort(np.abs(assembly.constrained_poles(boom.nodes, boom.pairs(), per_member, BASE)))
    assert np.max(np.abs(f / ref - 1)) < 1e-9
    fe = opensees_fe.frame_frequencies(boom.nodes, boom.pairs(), per_member, BASE, 10, "consistent", 20)
    assert np.max(np.abs(f[:20] / fe - 1)) < 5e-3
    # the most specific key wins: cube C2's diagonals, then cube C3, then the groups
    special = titop.Section.square(0.025)
    got = boom.sections({"C2/diagonals": special, "C3": stiff, "all": SEC})
    for m, s in zip(boom.members, got):
        assert s is (special if (m.cube, m.group) == ("C2", "diagonals") else stiff if m.cube == "C3" else SEC)


def test_the_h_parameter_of_a_general_truss_is_exact():
    h = Parameter("h", 0.03, 0.015, 0.03, tunable=True)
    boom = cubetruss.boom(2)
    model = cubetruss.truss_model(boom, titop.Section.square(0.02), BASE, ["N12"], h_param=h)
    for value in (0.015, 0.03):
        f1 = _frequencies(model.substitute({"h": value}))
        f2 = _frequencies(cubetruss.truss_model(boom, titop.Section.square(value), BASE, ["N12"]))
        assert f1.size == f2.size and np.max(np.abs(f1 / f2 - 1)) < 1e-9
    with pytest.raises(ValueError, match="one section for all members"):
        cubetruss.truss_model(boom, {"longerons": titop.Section.square(0.03), "all": SEC}, BASE, h_param=h)


@pytest.mark.parametrize("cubes, match", [
    ([], "at least one cube"),
    ([Cube("A", (0, 0, 0)), Cube("A", (0, 0, 1))], "names must differ"),
    ([Cube("A", (0, 0, 0)), Cube("B", (0.5, 0, 0))], "cubes A and B overlap"),
    ([Cube("A", (0, 0, 0)), Cube("B", (0, 0, 1), sides=(2, 2, 2))], "cubes A and B touch .* without sharing the corners"),
    ([Cube("A", (0, 0, 0)), Cube("B", (0.5, 0, 1))], "cubes A and B touch .* without sharing the corners"),
    ([Cube("A", (0, 0, 0)), Cube("B", (0, 0, 1)), Cube("C", (5, 0, 0))], r"cubes \['C'\] are connected to nothing"),
    ([Cube("A", (0, 0, 0), rotation=((0.8, -0.6, 0), (0.6, 0.8, 0), (0, 0, 1)))], "signed permutation"),
    ([Cube("A", (0, 0, 0), sides=(1, -1, 1))], "side ly must be a positive length"),
    ([Cube("A", (0, 0, 0), side="sideways")], "side must be one of"),
])
def test_a_bad_description_is_refused_naming_the_cubes(cubes, match):
    with pytest.raises(ValueError, match=match):
        cubetruss.cube_truss(cubes)


def test_bad_nodes_sections_and_sizes_are_refused():
    boom = cubetruss.boom(1)
    with pytest.raises(ValueError, match=r"nodes \['N99'\] are not nodes of the truss \(N1..N8\)"):
        cubetruss.truss_model(boom, SEC, BASE, ["N99"])
    with pytest.raises(ValueError, match="at least one node"):
        cubetruss.truss_model(boom, SEC, [])
    with pytest.raises(ValueError, match=r"\['N1'\] are both clamped and ports"):
        cubetruss.truss_model(boom, SEC, BASE, ["N1"])
    with pytest.raises(ValueError, match=r"section keys \['spars'\] name no cube or group"):
        boom.sections({"spars": SEC})
    with pytest.raises(ValueError, match=r"no section for the members \['C1/battens'\]"):
        boom.sections({"longerons": SEC, "diagonals": SEC})
    with pytest.raises(ValueError, match="n .number of cubes. must be an integer >= 1"):
        cubetruss.boom(0)
    with pytest.raises(ValueError, match=r"a \(cube side\) must be a number in \(0, 1000\] m, got -1"):
        cubetruss.boom(2, a=-1)
    with pytest.raises(ValueError, match="axis must be one of"):
        cubetruss.boom(2, axis="w")
    with pytest.raises(ValueError, match="m .cubes along y. must be an integer >= 1"):
        cubetruss.plate(2, 0)
    with pytest.raises(ValueError, match="or one per member: 2 sections for 13 members"):
        assembly.constrained_frequencies(boom.nodes, boom.pairs(), [SEC, SEC], BASE)
