"""Results files: JSON conversion, atomic writes, keyed caches, the moved-numbers report."""

from __future__ import annotations

import json
import pathlib
from dataclasses import dataclass

import numpy as np
import pytest
from trusscodesign.infra import results
from trusscodesign.model import spacecraft

INPUTS = spacecraft.inputs_key()  # what the stored designs of notebooks 06 and 07 are computed from


def _hammer(path: str, writer: int, n: int) -> int:
    """Write ``n`` payloads to ``path`` (one process of the concurrency test); returns the failures."""
    failures = 0
    for i in range(n):
        try:
            results.write_json(path, {"writer": writer, "i": i, "pad": list(range(200))})
        except OSError:
            failures += 1
    return failures


def test_complex_non_finite_and_complex64_give_valid_json() -> None:
    for value in (complex(np.inf, 1.0), np.complex128(complex(np.nan, 0.0)), np.complex64(1 + 2j), np.array([1j, np.inf + 0j])):
        json.dumps(results.to_jsonable(value), allow_nan=False)  # strict JSON: no Infinity / NaN tokens


def test_colliding_keys_are_refused_not_dropped() -> None:
    with pytest.raises(ValueError, match="collide"):
        results.to_jsonable({1: "a", "1": "b"})


def test_dataclass_is_converted() -> None:
    @dataclass
    class D:
        a: float = np.inf
        b: np.ndarray | None = None

    assert results.to_jsonable(D(b=np.arange(2))) == {"a": "inf", "b": [0, 1]}


def test_save_results_is_atomic(tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """An interrupt while the new file is being written (here: as it is flushed to disk) leaves the previous file
    whole and no temporary file behind."""
    import os

    results.save_results("x", {"J_c": 0.5}, tmp_path)

    def interrupted(fd: int) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "fsync", interrupted)
    with pytest.raises(KeyboardInterrupt):
        results.save_results("x", {"J_c": 0.7}, tmp_path)
    monkeypatch.undo()
    assert results.load_results("x", tmp_path)["results"] == {"J_c": 0.5}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.json"]


def test_load_results_restores_non_finite_floats(tmp_path: pathlib.Path) -> None:
    results.save_results("x", {"J_c": np.inf, "rows": [{"Z_c": np.nan}]}, tmp_path)
    r = results.load_results("x", tmp_path)["results"]
    assert r["J_c"] == np.inf and np.isnan(r["rows"][0]["Z_c"])


@pytest.mark.parametrize("key", [{"x": float("nan")}, {"norm": "inf"}, {"n": np.int64(3), "v": np.float32(0.5)}])
def test_read_keyed_reuses_a_file_written_with_the_same_key(tmp_path: pathlib.Path, key: dict) -> None:
    path = tmp_path / "c.json"
    _, k = results.read_keyed(path, key)
    results.write_json(path, {"key": k, "v": 1})
    assert results.read_keyed(path, key)[0] is not None


def test_read_keyed_keys_arrays_exactly(tmp_path: pathlib.Path) -> None:
    path = tmp_path / "c.json"
    for a, b in ((np.array([0.123456789012]), np.array([0.123456789099])), (np.arange(2000.0), np.r_[np.arange(1000.0), -1.0, np.arange(1001.0, 2000.0)])):
        _, k = results.read_keyed(path, {"a": a})
        results.write_json(path, {"key": k})
        assert results.read_keyed(path, {"a": a})[0] is not None
        assert results.read_keyed(path, {"a": b})[0] is None  # another array: not reused


def test_moved_numbers_name_each_number_beyond_its_tolerance() -> None:
    tol = {"J_c": ("rel", 1e-3), "theta": ("abs", 0.5)}
    stored = {"J_c": 0.91, "theta": 100.6}
    assert results.moved_numbers("case", {"J_c": 0.9109, "theta": 101.0}, stored, tol) == []
    moved = results.moved_numbers("nb 06b, preset", {"J_c": 0.95, "theta": 69.4}, stored, tol)
    assert len(moved) == 2 and moved[0].startswith("nb 06b, preset: J_c moved: 0.95 now, 0.91 stored (+4.4 %")
    assert "theta moved: 69.4 now, 100.6 stored (-31.2, tolerance 0.5)" in moved[1]
    # an unstable loop (infinite norm) matches only itself; differing inputs are said
    assert results.moved_numbers("c", {"J_c": np.inf, "theta": 1.0}, {"J_c": np.inf, "theta": 1.0}, tol) == []
    moved = results.moved_numbers("c", {"J_c": np.inf, "theta": 1.0}, {"J_c": 0.9, "theta": 1.0}, tol, {"p": 1, "m": 2}, {"p": 3, "m": 2})
    assert moved == ["c: J_c moved: inf now, 0.9 stored (an infinite norm is an unstable loop) (the inputs differ from the stored run's: p)"]
    with pytest.raises(KeyError, match="theta"):
        results.moved_numbers("c", {"J_c": 1.0}, stored, tol)
    assert results.moved_numbers("c", {"J_c": 0.0, "theta": np.nan}, {"J_c": 0.0, "theta": np.nan}, tol) == []
    moved = results.moved_numbers("c", {"J_c": 1e-9, "theta": np.nan}, {"J_c": 0.0, "theta": 1.0}, tol)
    assert [m.split(" (")[1] for m in moved] == ["+1e-09 from 0, tolerance relative)", "not a number)"]


def test_load_reference_checks_the_folder_before_any_work(tmp_path: pathlib.Path) -> None:
    assert results.load_reference("06_robust_synthesis", None) is None
    with pytest.raises(TypeError, match="reference_dir must be a folder"):
        results.load_reference("06_robust_synthesis", 3)
    with pytest.raises(FileNotFoundError, match=r"reference_dir = .*no stored results .*06_robust_synthesis\.json"):
        results.load_reference("06_robust_synthesis", str(tmp_path))
    results.save_results("06_robust_synthesis", {"designs": {}}, tmp_path, inputs=INPUTS)
    assert results.load_reference("06_robust_synthesis", str(tmp_path))["inputs"] == INPUTS


def test_complex_values_keep_real_and_imaginary_parts() -> None:
    assert results.to_jsonable(np.complex128(1.5 - 2.0j)) == {"re": 1.5, "im": -2.0}
    assert results.to_jsonable([complex(-np.inf, -3.0)]) == [{"re": "-inf", "im": -3.0}]


def test_non_finite_floats_round_trip_with_their_sign(tmp_path: pathlib.Path) -> None:
    payload = {"a": -np.inf, "b": [np.inf, np.float32(-np.inf)], "c": {"d": np.nan}, "e": -1.5}
    path = results.write_json(tmp_path / "x.json", payload)
    back = results.from_jsonable(json.loads(path.read_text()))
    assert back["a"] == -np.inf and back["b"] == [np.inf, -np.inf] and np.isnan(back["c"]["d"]) and back["e"] == -1.5


def test_design_models_give_g_r_as_a_named_statespace(model) -> None:
    """``DesignModels.G_r``: the reduced model's realisation, the Delta channels first, then the open loop's names."""
    import control as ct
    import numpy as np
    from trusscodesign.model import spacecraft
    from trusscodesign.study.design import DesignModels

    m = DesignModels(0.02139, model, model, model, np.eye(3), 0.0, 0.0)
    g = m.G_r
    assert isinstance(g, ct.StateSpace) and g.name == "G_r"
    nd = model.n_delta
    assert g.input_labels[nd:] == spacecraft.INPUTS and g.output_labels[nd:] == spacecraft.OUTPUTS
    assert all(label.startswith("w_") for label in g.input_labels[:nd]) and g.nstates == model.nstates
    np.testing.assert_array_equal(g.D, model.d)


def test_concurrent_writers_of_one_file_lose_nothing(tmp_path: pathlib.Path) -> None:
    """Four processes write one file 2000 times in all while this one reads it: no writer fails (a shared temporary
    name made some rename a file another writer had already moved), every read is a whole file, no temporary is left."""
    import multiprocessing as mp

    path = tmp_path / "shared.json"
    results.write_json(path, {"writer": -1, "i": 0, "pad": []})
    ctx = mp.get_context("fork")
    with ctx.Pool(4) as pool:
        pending = pool.starmap_async(_hammer, [(str(path), w, 500) for w in range(4)])
        reads = 0
        while not pending.ready():
            assert set(json.loads(path.read_text())) == {"writer", "i", "pad"}
            reads += 1
        assert pending.get() == [0, 0, 0, 0]
    assert reads > 0 and sorted(p.name for p in tmp_path.iterdir()) == ["shared.json"]


def test_a_truncated_checkpoint_names_the_file(tmp_path: pathlib.Path) -> None:
    from trusscodesign.study import pso

    path = tmp_path / "07_pso_checkpoint.json"
    results.write_json(path, {"iteration": 3, "x": [1.0, 2.0, 3.0]})
    path.write_text(path.read_text()[:20])
    with pytest.raises(ValueError, match=r"07_pso_checkpoint\.json is not valid JSON.*truncated"):
        pso.load_state(path)
    with pytest.raises(ValueError, match=r"07_pso_checkpoint\.json is not valid JSON"):
        results.read_keyed(path, {"a": 1})


def test_written_files_are_readable_as_ordinary_new_files(tmp_path: pathlib.Path) -> None:
    """mkstemp makes its file the owner's only: a results folder shared by a group must stay readable to it."""
    import os

    umask = os.umask(0o022)
    try:
        path = results.write_json(tmp_path / "r.json", {"a": 1})
    finally:
        os.umask(umask)
    assert path.stat().st_mode & 0o777 == 0o644
