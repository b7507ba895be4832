"""The spacecraft parameters against their schema: the stored file passes; a missing field or a bad value is refused
with the file (or "params"), the field's path, its unit and what is allowed, before any model is built."""

import copy
import json
import shutil

import numpy as np
import pytest
from trusscodesign.infra import paths
from trusscodesign.model import schema, spacecraft


def _edited(change) -> dict:
    params = copy.deepcopy(spacecraft.load_parameters())
    change(params)
    return params


def test_the_stored_parameters_pass():
    schema.check_parameters(spacecraft.load_parameters())


@pytest.mark.parametrize("change, match", [
    (lambda p: p["hub"].pop("mass"), r"the field hub\.mass is missing"),
    (lambda p: p.pop("closed_loop"), r"the field closed_loop\.omega_acs is missing \(closed_loop not found\)"),
    (lambda p: p["hub"].update(mass=-400.0), r"hub\.mass \[kg\] must be a finite number in \(0, inf\), got -400\.0"),
    (lambda p: p["hub"].update(mass="640"), r"hub\.mass \[kg\] must be a number, got str '640'"),
    (lambda p: p["truss"].update(damping=float("nan")), r"truss\.damping \[-\] must be a finite number in \[0, 1\)"),
    (lambda p: p["solar_panel"].update(omega=[2.51, 9.42, 3.77]), r"solar_panel\.omega \[rad/s\] must be a list of positive, increasing"),
    (lambda p: p["hub"]["inertia"][0].__setitem__(1, 50.0), r"hub\.inertia \[kg m\^2\] must be a symmetric positive definite"),
    (lambda p: p["choices"].update(effort="force"), r"choices\.effort \[-\] must be one of \['command', 'transmitted'\]"),
    (lambda p: p["truss"].update(damping_model="rayleigh"), r"truss\.damping_model \[-\] must be one of \['clamped_modes', 'stiffness'\]"),
    (lambda p: p["truss"].pop("damping_model"), r"the field truss\.damping_model is missing"),
    (lambda p: p["truss"].update(h_range=[0.03, 0.015]), r"truss\.h_range \[m\] must be \(low, high\) with 0 < low < high"),
    (lambda p: p["solar_panel"].pop("factors"), r"the field solar_panel\.factors is missing"),
    (lambda p: p["solar_panel"]["factors"].pop(), r"solar_panel\.factors must have one row per mode of solar_panel\.omega \(3\), got 2"),
])
def test_a_bad_field_is_named_with_its_unit_and_range(change, match):
    with pytest.raises(ValueError, match=r"params: " + match):
        spacecraft.open_loop(0.02139, params=_edited(change))


def test_an_edited_parameters_file_is_checked_on_load(tmp_path, monkeypatch):
    shutil.copytree(paths.PACKAGE_DATA, tmp_path / "data")
    path = tmp_path / "data" / "spacecraft" / "parameters.json"
    params = json.loads(path.read_text())
    del params["pma"]["stiffness"]
    path.write_text(json.dumps(params))
    monkeypatch.setattr(paths, "PACKAGE_DATA", tmp_path / "data")
    with pytest.raises(ValueError, match=rf"{path}: the field pma\.stiffness is missing"):
        spacecraft.load_parameters()
    path.write_text(path.read_text()[:100])
    with pytest.raises(ValueError, match=rf"{path} is not valid JSON"):
        spacecraft.load_parameters()


def test_an_edit_of_the_parameters_file_is_seen_by_a_running_kernel(tmp_path, monkeypatch):
    """The parameters (and their fingerprint, the key of stored results) follow the file: a kernel that loaded them
    before an edit does not go on with the old values."""
    shutil.copytree(paths.PACKAGE_DATA, tmp_path / "data")
    monkeypatch.setattr(paths, "PACKAGE_DATA", tmp_path / "data")
    path = tmp_path / "data" / "spacecraft" / "parameters.json"
    before = spacecraft.parameters_fingerprint()
    assert spacecraft.load_parameters()["hub"]["mass"] == 800.0
    params = json.loads(path.read_text())
    params["hub"]["mass"] = 400.0
    path.write_text(json.dumps(params, indent=2))
    assert spacecraft.load_parameters()["hub"]["mass"] == 400.0 and spacecraft.parameters_fingerprint() != before


def test_numpy_numbers_are_numbers():
    import numpy as np

    params = _edited(lambda p: p["hub"].update(mass=np.float32(640.0), mass_uncertainty=np.float64(0.2)))
    schema.check_parameters(params)


def test_the_damping_model_choice_reaches_the_beams():
    """with_choices(truss_damping_model=...) is what notebooks 04 and 06 vary: the truss's poles move, a bad name is refused."""
    ref = spacecraft.open_loop(0.02139).blocks["truss"].poles()
    stiff = spacecraft.open_loop(0.02139, params=spacecraft.with_choices(truss_damping_model="stiffness")).blocks["truss"].poles()
    assert not np.allclose(np.sort_complex(ref), np.sort_complex(stiff))
    with pytest.raises(ValueError, match=r"truss_damping_model must be one of \['clamped_modes', 'stiffness'\], got 'beta'"):
        spacecraft.with_choices(truss_damping_model="beta")
