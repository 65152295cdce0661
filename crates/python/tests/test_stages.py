"""The Python package against the Rust stages: kinds, generated functions,
a BEM curve equal to the one the Rust bridge test pins, and refused
parameters raised as ValueError with the YAML message.

Build first: `pip install ./crates/python` (or `maturin develop --release`).
"""

import inspect
from pathlib import Path

import numpy as np
import polars as pl
import pytest

import hypercontact
from hypercontact import Field, stages

# bem's last load_n on `surface_m()` with BEM_PARAMS, as computed by the Rust
# stage in crates/python/tests/bridge.rs (PINNED_LAST_LOAD_N): equality means
# the map, the material table and the parameters crossed unchanged.
RUST_LAST_LOAD_N = 8.66976747881934e-06

BEM_PARAMS = dict(boundary="periodic", model="linear", steps=5,
                  max_area_fraction=0.1, map_fractions=[0.1])


def surface_m():
    """The map of bridge.rs: every height an exact IEEE product."""
    ix, iy = np.meshgrid(np.arange(32), np.arange(32), indexing="ij")
    return ((3 * ix * ix + 5 * iy + ix * iy) % 23).astype(np.float64) * 1e-8


def test_kinds_lists_bem_and_fem_with_docs():
    kinds = {k.kind: k for k in hypercontact.kinds()}
    assert "bem" in kinds and "fem" in kinds
    assert kinds["bem"].version >= 1 and kinds["bem"].doc
    assert set(stages.__all__) == {k.replace("-", "_") for k in kinds}


def test_generated_function_carries_declared_params_and_docs():
    signature = inspect.signature(stages.bem)
    assert signature.parameters["steps"].default == 40
    assert signature.parameters["boundary"].default == "free"
    assert "surface" in signature.parameters
    assert "max_area_fraction" in stages.bem.__doc__
    assert "Boundary elements" in stages.bem.__doc__


def test_material_preset_is_a_dataframe():
    material = stages.material_preset()
    assert isinstance(material, pl.DataFrame)
    assert material.columns == ["model", "param", "value"]
    assert material.height > 0


def test_bem_from_python_equals_the_rust_stage():
    material = stages.material_preset()
    out = stages.bem(surface=Field(surface_m(), 1e-6), material=material, **BEM_PARAMS)
    response = out["response"]
    assert isinstance(response, pl.DataFrame)
    load_n = response["load_n"].to_list()
    assert len(load_n) == 6
    assert load_n[0] == 0.0
    assert load_n[-1] == RUST_LAST_LOAD_N
    maps = out["contact_maps"]
    assert sorted(maps) == ["gap_a0.100.npy", "pressure_a0.100.npy"]
    assert maps.index.height == 1


def test_generic_stage_call_equals_the_generated_function():
    material = stages.material_preset()
    surface = Field(surface_m(), 1e-6)
    generic = hypercontact.stage("bem", {"surface": surface, "material": material}, **BEM_PARAMS)
    generated = stages.bem(surface=surface, material=material, **BEM_PARAMS)
    assert generic["response"].equals(generated["response"])


def test_a_bad_parameter_raises_value_error_naming_it():
    material = stages.material_preset()
    with pytest.raises(ValueError, match=r"parameter `steps`: must lie in \[1, 100000\], got 0"):
        stages.bem(surface=Field(surface_m(), 1e-6), material=material, steps=0)
    with pytest.raises(ValueError, match="boundary"):
        stages.bem(surface=Field(surface_m(), 1e-6), material=material, boundary="round")


def test_an_unknown_kind_raises_value_error():
    with pytest.raises(ValueError, match="unknown stage kind `nope`"):
        hypercontact.stage("nope")


def test_a_field_must_be_two_dimensional():
    with pytest.raises(ValueError, match="2-D"):
        Field(np.zeros(4), 1e-6)


def test_a_table_without_a_required_column_is_refused_naming_it():
    material = stages.material_preset().drop("value")
    with pytest.raises(ValueError, match=r"input `material`: no column `value` \(required: model, param, value\)"):
        stages.bem(surface=Field(surface_m(), 1e-6), material=material, **BEM_PARAMS)


def test_a_pandas_table_gives_what_the_polars_one_gives():
    pd = pytest.importorskip("pandas")
    material = stages.material_preset()
    as_pandas = pd.DataFrame({c: material[c].to_list() for c in material.columns})
    surface = Field(surface_m(), 1e-6)
    from_polars = stages.bem(surface=surface, material=material, **BEM_PARAMS)["response"]
    from_pandas = stages.bem(surface=surface, material=as_pandas, **BEM_PARAMS)["response"]
    assert from_pandas.equals(from_polars)


def test_file_outputs_are_paths_in_the_folder_asked_for(tmp_path):
    material = stages.material_preset()
    out = stages.bem(surface=Field(surface_m(), 1e-6), material=material,
                     out_dir=tmp_path / "maps", **BEM_PARAMS)
    maps = out["contact_maps"]
    assert maps.folder == tmp_path / "maps"
    assert sorted(maps) == ["gap_a0.100.npy", "pressure_a0.100.npy"]
    pressure_pa = np.load(maps["pressure_a0.100.npy"])
    assert pressure_pa.shape == (32, 32) and (pressure_pa > 0).mean() > 0.05
    # The index beside the files, as in a run folder.
    assert (tmp_path / "maps" / "contact_maps.parquet").is_file()
    # A folder of files goes back in as a files input.
    again = hypercontact.Files.from_folder(tmp_path / "maps")
    assert "pressure_a0.100.npy" in again


def test_required_inputs_have_no_default_and_reserved_keywords_exist():
    signature = inspect.signature(stages.bem)
    assert signature.parameters["surface"].default is inspect.Parameter.empty
    assert signature.parameters["replicates"].default is None
    assert signature.parameters["out_dir"].default is None
    assert signature.parameters["progress"].default is None


def test_progress_is_quiet_where_stderr_is_no_terminal_unless_asked(capsys):
    # pytest captures stderr, as a notebook's kernel does.
    assert hypercontact._progress_mode(None) is None
    material = stages.material_preset()
    stages.bem(surface=Field(surface_m(), 1e-6), material=material, **BEM_PARAMS)
    assert capsys.readouterr().err == ""
    # Asked for, it comes as lines on sys.stderr (what a notebook shows).
    stages.bem(surface=Field(surface_m(), 1e-6), material=material, progress=True, **BEM_PARAMS)
    err = capsys.readouterr().err
    assert "bem: " in err and "/5 (" in err, err
    # Or to a callable of one's own.
    lines = []
    stages.bem(surface=Field(surface_m(), 1e-6), material=material, progress=lines.append, **BEM_PARAMS)
    assert any(line.startswith("bem: ") for line in lines), lines


def test_the_stub_covers_every_generated_function():
    stub = (Path(hypercontact.__file__).parent / "stages.pyi").read_text()
    for name in stages.__all__:
        assert f"\ndef {name}(\n" in stub, name


def test_a_stage_warning_is_a_python_warning_at_the_callers_line():
    import warnings
    from conftest import REPO
    height = stages.height_map(path=REPO / "data" / "reference" / "topography" / "sur-2.sur")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        stages.surface(height=height, resolution_m=0)
    messages = [str(w.message) for w in caught]
    assert any(m.startswith("surface: the PSD along x is a poor power law") for m in messages), messages
    assert all(w.category is UserWarning and w.filename == __file__ for w in caught)


def test_tables_carry_their_declared_units_and_docs(tmp_path):
    out = stages.bem(surface=Field(surface_m(), 1e-6), material=stages.material_preset(), **BEM_PARAMS)
    response = out["response"]
    assert response.units["load_n"] == "N"
    assert response.units["z_m"] == "m"
    assert response.docs["load_n"]
    # As the Parquet file holds them: polars reads the same key.
    response.write_parquet(tmp_path / "copy.parquet")  # a copy made in Python has none
    assert hypercontact.read_table(tmp_path / "copy.parquet").units == {}


# The CLI's `.npy` reader refuses these value types in these words (#50, item 9).
@pytest.mark.parametrize("values, descr", [
    (np.arange(16, dtype=np.int64).reshape(4, 4), "'<i8'"),
    (np.zeros((4, 4), dtype=bool), "'|b1'"),
    (np.ones((4, 4), dtype=complex), "'<c16'"),
    (np.full((4, 4), 1.0, dtype=object), "'|O'"),
], ids=["int64", "bool", "complex", "object"])
def test_a_field_refuses_what_the_cli_npy_reader_refuses(values, descr):
    message = f"Field: heights_m: the values are `{descr}`, not float64 or float32"
    with pytest.raises(ValueError) as refused:
        Field(values, 1e-6)
    assert str(refused.value) == message


def test_float32_and_big_endian_heights_are_read_as_the_cli_reads_them():
    single = Field(np.ones((2, 3), dtype=np.float32), 1e-6)
    swapped = Field(np.ones((2, 3), dtype=">f8"), 1e-6)
    assert single.heights_m.dtype == np.float64 and single == swapped


def test_a_scalar_or_none_is_named_not_called_one_dimensional():
    with pytest.raises(ValueError) as scalar:
        Field(np.array(2.0), 1e-6)
    assert str(scalar.value) == "Field: heights_m: the array has shape (), not 2-D"
    with pytest.raises(ValueError) as none:
        Field(None, 1e-6)
    assert str(none.value).endswith("got None")


@pytest.mark.parametrize("value, shown", [
    (float("nan"), "NaN"), (float("inf"), "inf"), (np.float64("-inf"), "-inf"),
])
def test_a_non_finite_parameter_is_refused_naming_it(value, shown):
    with pytest.raises(ValueError) as refused:
        stages.material(mu_pa=value)
    assert str(refused.value) == f"material: parameter `mu_pa`: `{shown}` is not a finite number"
    with pytest.raises(ValueError, match=r"parameter `map_fractions\.1`: "):
        stages.bem(surface=Field(surface_m(), 1e-6), material=stages.material_preset(),
                   map_fractions=[0.1, value])
