"""hypercontact from Python: every stage of the Rust workspace as a function,
and the pipeline runner with the CLI's cache.

Nothing here is written per stage. ``stage(kind, inputs, **params)`` calls any
registered kind through the compiled module ``_hypercontact`` with the
pipeline's parameter path, so parameters get the defaults, checks and error
messages (raised as ``ValueError``) that a YAML ``with:`` block gets; the
functions in ``hypercontact.stages`` are generated at import from the kinds'
own declarations (``hypercontact stages --json``), and ``stages.pyi`` gives an
editor their parameters, types and docs.

Products cross as: tables <-> polars DataFrames (pandas accepted as input;
Parquet bytes written and read by the runner's own code, the declared units
and descriptions attached as ``frame.units`` / ``frame.docs``), fields <->
``Field`` (a 2-D float64 array, axis 0 = x, with its spacing in metres), files
-> ``Files`` (paths in a folder, with the index table when the output
declares one).

``run(pipeline)`` and ``study(pipeline)`` run a pipeline file as
``hypercontact run`` / ``hypercontact study`` do, in the same folders and with
the same cache; ``load(run_dir)`` reads a finished run back.
"""

from __future__ import annotations

import inspect
import io
import json
import os
import sys
import tempfile
import types
import warnings
from pathlib import Path
from typing import Any, Dict, Iterator, List, Mapping, NamedTuple, Optional, Sequence, Union

import numpy as np
import polars as pl

from . import _hypercontact

__all__ = [
    "Field", "Files", "Kind", "Run", "Study", "describe", "kinds", "load", "run", "stage",
    "stages", "study",
]

PathLike = Union[str, "os.PathLike[str]"]
#: A table input: a polars DataFrame, or a pandas one (converted with polars).
Table = Any
#: A files input: ``Files``, a folder, or a mapping name -> path or bytes.
FilesLike = Any

# The key under which the runner stores each declared column's unit and
# description in a Parquet file's key-value metadata.
_COLUMNS_KEY = "hypercontact:columns"


class Field:
    """A 2-D field on a regular grid: ``heights_m[ix, iy]`` (NaN = not
    measured), spacing ``dx_m`` along axis 0 and ``dy_m`` along axis 1
    (``dy_m`` defaults to ``dx_m``). The values need not be heights: a
    pressure map holds pascals in the same array."""

    __slots__ = ("heights_m", "dx_m", "dy_m")

    def __init__(self, heights_m: Any, dx_m: float, dy_m: Optional[float] = None):
        if heights_m is None:
            raise ValueError("Field: heights_m must be a 2-D array of float64 or float32, got None")
        given = np.asarray(heights_m)
        # The CLI's `.npy` reader judges the same descriptor in the same words:
        # integers would be taken as metres, complex numbers lose their
        # imaginary part, and a scalar is no map.
        descr = np.lib.format.dtype_to_descr(given.dtype)
        try:
            _hypercontact.check_field_values(repr(descr), list(given.shape))
        except ValueError as e:
            raise ValueError(f"Field: heights_m: {e}") from None
        self.heights_m = np.ascontiguousarray(given, dtype=np.float64)
        self.dx_m = float(dx_m)
        self.dy_m = float(dx_m if dy_m is None else dy_m)

    @property
    def shape(self):
        return self.heights_m.shape

    @property
    def values(self) -> np.ndarray:
        """The array, under a name that fits a field of anything."""
        return self.heights_m

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, Field)
            and self.dx_m == other.dx_m
            and self.dy_m == other.dy_m
            and np.array_equal(self.heights_m, other.heights_m, equal_nan=True)
        )

    def __repr__(self) -> str:
        nx, ny = self.shape
        return f"Field({nx} x {ny}, dx_m={self.dx_m!r}, dy_m={self.dy_m!r})"


class Files(Mapping[str, Path]):
    """Named files a stage wrote, as paths in ``folder`` (``files[name]``),
    and, when the output declares one, their ``index`` table (which file
    holds what)."""

    def __init__(self, folder: PathLike, names: Sequence[str], index: Optional[pl.DataFrame] = None):
        self.folder = Path(folder)
        self._names = sorted(names)
        self.index = index

    @classmethod
    def from_folder(cls, folder: PathLike) -> "Files":
        """Every file under ``folder`` (recursively), named by its path
        relative to it."""
        root = Path(folder)
        if not root.is_dir():
            raise ValueError(f"{root}: not a folder of files")
        names = [p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file()]
        return cls(root, names)

    def __getitem__(self, name: str) -> Path:
        if name not in self._names:
            raise KeyError(name)
        return self.folder / name

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)

    def __repr__(self) -> str:
        index = "yes" if self.index is not None else "no"
        return f"Files({str(self.folder)!r}, {self._names!r}, index={index})"


class Kind(NamedTuple):
    """A stage kind as registered: its name after ``uses:``, version,
    one-line summary and full doc."""

    kind: str
    version: int
    summary: str
    doc: str


def kinds() -> List[Kind]:
    """Every stage kind this build knows, in name order."""
    return [Kind(*k) for k in _hypercontact.kinds()]


def describe(kind: str) -> Dict[str, Any]:
    """The kind's declaration as ``hypercontact stages --json`` prints it:
    params (name, default, unit, doc, ...), inputs and outputs."""
    return json.loads(_hypercontact.describe(kind))


def _with_units(frame: pl.DataFrame, source: Any) -> pl.DataFrame:
    """Attaches the units and descriptions a Parquet file carries as
    ``frame.units`` and ``frame.docs`` (column -> text). They live on this
    object only: a new frame made from it does not keep them."""
    try:
        if isinstance(source, (bytes, bytearray)):
            source = io.BytesIO(source)
        meta = pl.read_parquet_metadata(source)
        columns = json.loads(meta.get(_COLUMNS_KEY, "[]"))
    except Exception:  # a file without the key, or a reader without metadata
        columns = []
    frame.units = {c["name"]: c["unit"] for c in columns}
    frame.docs = {c["name"]: c["doc"] for c in columns}
    return frame


def read_table(path: PathLike) -> pl.DataFrame:
    """A Parquet table as the runner wrote it, with its units attached."""
    return _with_units(pl.read_parquet(path), str(path))


def read_field(npy: PathLike) -> Field:
    """A field as the runner exports it: ``name.npy`` beside ``name.grid.json``."""
    npy = Path(npy)
    grid = npy.with_suffix(".grid.json")
    values, dx_m, dy_m = _hypercontact.read_field(str(npy), str(grid))
    return Field(values, dx_m, dy_m)


def _parquet_bytes(frame: pl.DataFrame) -> bytes:
    buffer = io.BytesIO()
    frame.write_parquet(buffer)
    return buffer.getvalue()


def _as_polars(name: str, value: Any) -> Optional[pl.DataFrame]:
    if isinstance(value, pl.DataFrame):
        return value
    if type(value).__module__.startswith("pandas") and type(value).__name__ == "DataFrame":
        return _from_pandas(name, value)
    return None


def _from_pandas(name: str, frame: Any) -> pl.DataFrame:
    """A pandas table column by column, so no pyarrow is needed: numbers as
    their numpy arrays, anything else as text (the three column types a
    stage reads)."""
    columns = {}
    for column in frame.columns:
        series = frame[column]
        kind = getattr(series.dtype, "kind", "O")
        if kind in "iuf":
            columns[str(column)] = series.to_numpy()
        elif kind == "b":
            raise ValueError(f"input `{name}`: column `{column}` is boolean; stages read numbers and text")
        else:
            columns[str(column)] = [None if v is None or v != v else str(v) for v in series.tolist()]
    return pl.DataFrame(columns)


def _files_product(name: str, value: Any):
    if isinstance(value, (str, os.PathLike)) and Path(value).is_dir():
        value = Files.from_folder(value)
    if isinstance(value, Files):
        files = {n: value[n].read_bytes() for n in value}
        index = None if value.index is None else _parquet_bytes(value.index)
        return ("files", files, index)
    if isinstance(value, Mapping):
        files = {}
        for n, v in value.items():
            files[str(n)] = bytes(v) if isinstance(v, (bytes, bytearray)) else Path(v).read_bytes()
        return ("files", files, None)
    return None


def _to_product(name: str, value: Any):
    if isinstance(value, Field):
        return ("field", value.heights_m, value.dx_m, value.dy_m)
    frame = _as_polars(name, value)
    if frame is not None:
        return ("table", _parquet_bytes(frame))
    files = _files_product(name, value)
    if files is not None:
        return files
    raise ValueError(
        f"input `{name}`: expected a DataFrame (polars or pandas), a Field, Files or a "
        f"folder, got {type(value).__name__}"
    )


def _flatten_inputs(inputs: Mapping[str, Any], files_inputs: set, prefix: str = "") -> Dict[str, Any]:
    """Labelled inputs (``{"responses": {"T1": df}}``) as the stage sees them:
    ``responses.T1``. A mapping given for a files input is that input's
    files, not labels."""
    flat = {}
    for name, value in inputs.items():
        key = f"{prefix}{name}"
        top = key.split(".")[0]
        if isinstance(value, Mapping) and not isinstance(value, Files) and not (
            top in files_inputs and _looks_like_files(value)
        ):
            flat.update(_flatten_inputs(value, files_inputs, key + "."))
        else:
            flat[key] = _to_product(key, value)
    return flat


def _looks_like_files(value: Mapping) -> bool:
    return all(isinstance(v, (bytes, bytearray, str, os.PathLike)) for v in value.values())


def _json_default(value: Any):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise TypeError(f"{type(value).__name__} is not a parameter value")


def _terminal() -> bool:
    stream = sys.stderr
    return bool(stream is not None and hasattr(stream, "isatty") and stream.isatty())


def _write_line(line: str) -> None:
    sys.stderr.write(line)
    sys.stderr.flush()


def _progress_mode(progress: Any):
    """What the compiled module is told: None (quiet), True (the runner's
    bars on a terminal) or a callable taking a line of text. By default bars
    where a person watches a terminal and nothing in a notebook (whose
    stderr is no terminal); asked for there, progress comes as lines on
    ``sys.stderr``, which the notebook shows. A callable of your own (a
    logger) gets the lines instead."""
    if callable(progress):
        return progress
    if progress is None:
        return True if _terminal() else None
    if not progress:
        return None
    return True if _terminal() else _write_line


def _say_notes(kind: str, notes: Sequence[str], stacklevel: int) -> None:
    """A stage's warnings as Python warnings (its other notes were shown
    with the progress and are in a run's provenance)."""
    for note in notes:
        if note.startswith("warning:"):
            # Shown at the caller's line, not at this module's.
            warnings.warn(f"{kind}: {note[len('warning:'):].strip()}", stacklevel=stacklevel + 1)


def _write_files(kind: str, output: str, product, out_dir: Optional[PathLike]) -> Files:
    folder = Path(out_dir) if out_dir is not None else Path(
        tempfile.mkdtemp(prefix=f"hypercontact-{kind}-")
    )
    folder.mkdir(parents=True, exist_ok=True)
    files, index = product[1], product[2]
    for name, data in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    frame = None
    if index is not None:
        # Beside the files under the output's name, as a run folder has it.
        (folder / f"{output}.parquet").write_bytes(index)
        frame = _with_units(pl.read_parquet(io.BytesIO(index)), index)
    return Files(folder, list(files), frame)


def _from_product(kind: str, output: str, product, out_dir: Optional[PathLike]):
    tag = product[0]
    if tag == "table":
        return _with_units(pl.read_parquet(io.BytesIO(product[1])), product[1])
    if tag == "field":
        return Field(product[1], product[2], product[3])
    return _write_files(kind, output, product, out_dir)


def stage(
    kind: str,
    inputs: Optional[Mapping[str, Any]] = None,
    *,
    out_dir: Optional[PathLike] = None,
    progress: Optional[bool] = None,
    **params: Any,
) -> Dict[str, Any]:
    """Runs stage ``kind`` on ``inputs`` (name -> DataFrame, Field or Files;
    a dict of them for a labelled input) with ``params`` as in a pipeline's
    ``with:`` block; returns output name -> DataFrame, Field or Files.

    File outputs are written into ``out_dir`` (default: a new temporary
    folder). Relative paths in parameters resolve against the current
    directory. A refused parameter or input raises ``ValueError`` with the
    CLI's message; the stage's warnings are Python warnings, its other notes
    are printed with the progress."""
    return _call(kind, inputs, out_dir, progress, params, stacklevel=3)


def _not_finite(value: Any, path: str) -> Optional[str]:
    """The first NaN or infinite float in a parameter value, named by its
    dotted path as a YAML value's message names it; None when all are
    finite."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, Mapping):
        for key, item in value.items():
            found = _not_finite(item, f"{path}.{key}")
            if found is not None:
                return found
        return None
    if isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            found = _not_finite(item, f"{path}.{i}")
            if found is not None:
                return found
        return None
    if isinstance(value, (float, np.floating)) and not np.isfinite(value):
        return f"parameter `{path}`: {_hypercontact.not_finite(float(value))}"
    return None


def _call(kind, inputs, out_dir, progress, params, stacklevel: int) -> Dict[str, Any]:
    for name, value in params.items():
        found = _not_finite(value, name)
        if found is not None:
            raise ValueError(f"{kind}: {found}")
    try:
        params_json = json.dumps(params, default=_json_default, allow_nan=False)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{kind}: parameters: {e}") from None
    files_inputs = {
        i["name"] for i in _declaration(kind)["inputs"] if i["kind"] == "files"
    }
    products = _flatten_inputs(inputs or {}, files_inputs)
    outputs, notes = _hypercontact.run_stage(kind, products, params_json, _progress_mode(progress))
    _say_notes(kind, notes, stacklevel)
    return {name: _from_product(kind, name, p, out_dir) for name, p in outputs.items()}


_DECLARATIONS: Dict[str, Dict[str, Any]] = {}


def _declaration(kind: str) -> Dict[str, Any]:
    if kind not in _DECLARATIONS:
        _DECLARATIONS[kind] = describe(kind)
    return _DECLARATIONS[kind]


# ---------------------------------------------------------------- runs


class Products(Mapping[str, Any]):
    """A run's exported products keyed ``"stage.output"``, read from the run
    folder when first asked for (a paper run holds gigabytes)."""

    def __init__(self, out_dir: Path, provenance: Mapping[str, Any]):
        self._out_dir = out_dir
        self._where: Dict[str, tuple] = {}
        for stage_name, record in provenance.get("stages", {}).items():
            if record.get("temp"):
                continue  # dropped once read: never exported
            exported = [f.split("/", 1)[1] for f in record.get("outputs", {})]
            for output, owned in _owned_files(record["kind"], exported).items():
                self._where[f"{stage_name}.{output}"] = (stage_name, output, owned)
        self._loaded: Dict[str, Any] = {}

    def __getitem__(self, key: str) -> Any:
        if key not in self._loaded:
            stage_name, output, owned = self._where[key]
            self._loaded[key] = _read_output(self._out_dir / stage_name, output, owned)
        return self._loaded[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._where)

    def __len__(self) -> int:
        return len(self._where)

    def __repr__(self) -> str:
        return f"Products({len(self)} in {str(self._out_dir)!r})"


def _owned_files(kind: str, exported: Sequence[str]) -> Dict[str, tuple]:
    """Which exported files of a stage hold which output: a table is
    ``<output>.parquet``, a field ``<output>.npy`` with its grid, a files
    output every other file (with ``<output>.parquet`` as its index)."""
    outputs = _declaration(kind)["outputs"]
    claimed = set()
    owned: Dict[str, tuple] = {}
    for o in outputs:
        name = o["name"]
        if o["kind"] == "table":
            owned[name] = ("table", f"{name}.parquet")
            claimed.add(f"{name}.parquet")
        elif o["kind"] == "field":
            owned[name] = ("field", f"{name}.npy")
            claimed.update({f"{name}.npy", f"{name}.grid.json"})
        else:
            claimed.add(f"{name}.parquet")
    files_outputs = [o["name"] for o in outputs if o["kind"] == "files"]
    rest = [f for f in exported if f not in claimed]
    for name in files_outputs:
        index = f"{name}.parquet" if f"{name}.parquet" in exported else None
        # Outputs of one stage share its folder: with several files outputs,
        # each takes the files its index names.
        owned[name] = ("files", rest, index, len(files_outputs) > 1)
    return {k: v for k, v in owned.items() if _is_exported(v, exported)}


def _is_exported(where: tuple, exported: Sequence[str]) -> bool:
    return where[0] == "files" or where[1] in exported


def _read_output(folder: Path, output: str, where: tuple) -> Any:
    if where[0] == "table":
        return read_table(folder / where[1])
    if where[0] == "field":
        return read_field(folder / where[1])
    index = None if where[2] is None else read_table(folder / where[2])
    names = where[1]
    if where[3]:
        named = set()
        if index is not None:
            for column in index.columns:
                if index[column].dtype == pl.Utf8:
                    named.update(index[column].to_list())
        names = [n for n in names if n in named]
    return Files(folder, names, index)


class Run(Mapping[str, Any]):
    """A pipeline run: ``run["stage.output"]`` is a product (DataFrame,
    Field or Files), ``provenance`` what every stage was and read,
    ``out_dir`` its folder; after ``run()`` also ``summary`` (the CLI's
    lines) and the counts ``computed`` and ``cached``."""

    def __init__(self, out_dir: PathLike, summary: str = "", computed: int = 0, cached: int = 0):
        self.out_dir = Path(out_dir)
        record = self.out_dir / "provenance.json"
        if not record.is_file():
            raise ValueError(f"{self.out_dir}: no provenance.json: not a hypercontact run folder")
        self.provenance = json.loads(record.read_text())
        self.products = Products(self.out_dir, self.provenance)
        self.summary = summary
        self.computed = computed
        self.cached = cached

    def __getitem__(self, key: str) -> Any:
        try:
            return self.products[key]
        except KeyError:
            raise KeyError(f"{key!r}: no such product in {self.out_dir} "
                           "(keys are \"stage.output\"; temporary stages are not exported)") from None

    def __iter__(self) -> Iterator[str]:
        return iter(self.products)

    def __len__(self) -> int:
        return len(self.products)

    def __repr__(self) -> str:
        return f"Run({str(self.out_dir)!r}, {len(self)} products)"


def load(run_dir: PathLike) -> Run:
    """A finished run read back from its folder (``runs/<name>/`` or
    ``--out``): products keyed ``"stage.output"`` and its provenance."""
    return Run(run_dir)


def _sets(set: Union[None, Mapping[str, Any], Sequence[str]]) -> List[str]:
    """``--set`` assignments from a mapping (``{"t1-bem.steps": 20}``; values
    as JSON, which YAML reads) or from ``STAGE.PARAM=VALUE`` strings."""
    if set is None:
        return []
    if isinstance(set, Mapping):
        return [f"{k}={json.dumps(v, default=_json_default)}" for k, v in set.items()]
    if isinstance(set, str):
        return [set]
    return [str(s) for s in set]


def _force(force: Union[None, str, Sequence[str]]) -> List[str]:
    if force is None:
        return []
    return [force] if isinstance(force, str) else list(force)


def run(
    pipeline: PathLike,
    out: Optional[PathLike] = None,
    cache: Optional[PathLike] = None,
    set: Union[None, Mapping[str, Any], Sequence[str]] = None,
    force: Union[None, str, Sequence[str]] = None,
    only: Optional[str] = None,
    progress: Optional[bool] = None,
) -> Run:
    """Runs a pipeline file as ``hypercontact run`` does: outputs in ``out``
    (default ``runs/<name>/``), the cache beside the pipeline unless
    ``cache`` is given (the CLI's, so either reuses the other's results),
    ``set`` as ``--set`` (a mapping ``{"stage.param": value}`` or strings),
    ``force`` and ``only`` as the flags. Returns the ``Run``; a failure
    raises ``ValueError`` with the CLI's message."""
    mode = _progress_mode(progress)
    out_dir, summary, computed, cached = _hypercontact.run_pipeline(
        os.fspath(pipeline),
        None if out is None else os.fspath(out),
        None if cache is None else os.fspath(cache),
        _sets(set),
        _force(force),
        only,
        mode is True,
    )
    run = Run(out_dir, summary, computed, cached)
    if mode is not None:
        # The CLI's closing lines, where this process's reader sees them.
        say = _write_line if mode is True else mode
        say(f"{summary}{computed} ran, {cached} cached; outputs in {out_dir}\n")
    return run


class Study:
    """A study: ``tables["stage.output"]`` the gathered tables (one row
    block per variant, tagged with its values), ``variants`` one
    ``(values, Run)`` per variant, ``out_dir`` its folder."""

    def __init__(self, out_dir: PathLike, tables: Sequence[tuple]):
        self.out_dir = Path(out_dir)
        self.tables = {target: read_table(path) for target, path in tables}
        record = json.loads((self.out_dir / "study.json").read_text())
        self.variants = [(v["values"], Run(v["out_dir"])) for v in record]

    def __repr__(self) -> str:
        return f"Study({str(self.out_dir)!r}, {len(self.variants)} variants, tables {sorted(self.tables)})"


def study(
    pipeline: PathLike,
    out: Optional[PathLike] = None,
    cache: Optional[PathLike] = None,
    set: Union[None, Mapping[str, Any], Sequence[str]] = None,
    progress: Optional[bool] = None,
) -> Study:
    """Runs the pipeline's ``study:`` sweep as ``hypercontact study`` does
    and returns the ``Study``."""
    out_dir, tables = _hypercontact.run_study(
        os.fspath(pipeline),
        None if out is None else os.fspath(out),
        None if cache is None else os.fspath(cache),
        _sets(set),
        _progress_mode(progress) is True,
    )
    return Study(out_dir, tables)


# ---------------------------------------------------------------- stages


def _attribute(kind: str) -> str:
    return _hypercontact.attribute(kind)


def _signature(decl: Dict[str, Any]) -> inspect.Signature:
    keyword_only = inspect.Parameter.KEYWORD_ONLY
    parameters = []
    for i in decl["inputs"]:
        required = i["arity"] in ("one", "oneormore")
        default = inspect.Parameter.empty if required else None
        parameters.append(inspect.Parameter(i["name"], keyword_only, default=default))
    for p in decl["params"]:
        default = inspect.Parameter.empty if p.get("required") else p.get("default")
        parameters.append(inspect.Parameter(p["name"], keyword_only, default=default))
    parameters.append(inspect.Parameter("out_dir", keyword_only, default=None))
    parameters.append(inspect.Parameter("progress", keyword_only, default=None))
    return inspect.Signature(parameters)


def _stage_function(kind: str):
    decl = _declaration(kind)
    input_names = [i["name"] for i in decl["inputs"]]
    single = decl["outputs"][0]["name"] if len(decl["outputs"]) == 1 else None

    def call(**kwargs: Any):
        inputs = {n: kwargs.pop(n) for n in input_names if kwargs.get(n) is not None}
        for n in input_names:
            kwargs.pop(n, None)
        out_dir, progress = kwargs.pop("out_dir", None), kwargs.pop("progress", None)
        outputs = _call(kind, inputs, out_dir, progress, kwargs, stacklevel=3)
        return outputs[single] if single is not None else outputs

    call.__name__ = call.__qualname__ = _attribute(kind)
    call.__doc__ = _hypercontact.docstring(kind)
    call.__signature__ = _signature(decl)
    call.__module__ = "hypercontact.stages"
    return call


def _stages_module() -> types.ModuleType:
    module = types.ModuleType(
        "hypercontact.stages",
        "Every stage kind as a function (hyphens as underscores), generated at "
        "import from the kinds' declarations; one output is returned as it is, "
        "several as a dict.",
    )
    for k in kinds():
        setattr(module, _attribute(k.kind), _stage_function(k.kind))
    module.__all__ = sorted(_attribute(k.kind) for k in kinds())
    return module


stages = _stages_module()
sys.modules["hypercontact.stages"] = stages
