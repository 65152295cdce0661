"""hypercontact from Python: every stage of the Rust workspace as a function.

Nothing here is written per stage. ``stage(kind, inputs, **params)`` calls any
registered kind through the compiled module ``_hypercontact`` with the
pipeline's parameter path, so parameters get the defaults, checks and error
messages (raised as ``ValueError``) that a YAML ``with:`` block gets; the
functions in ``hypercontact.stages`` are generated at import from the kinds'
own declarations (``hypercontact stages --json``).

Products cross as: tables <-> polars DataFrames (Parquet bytes, written and
read by the same code as the runner's cache), fields <-> ``Field`` (a 2-D
float64 array, axis 0 = x, with its spacing in metres), files <-> ``Files``
(name -> bytes, with the index table when the output declares one).
"""

from __future__ import annotations

import inspect
import io
import json
import keyword
import sys
import types
from typing import Any, Dict, List, NamedTuple, Optional

import numpy as np
import polars as pl

from . import _hypercontact

__all__ = ["Field", "Files", "Kind", "describe", "kinds", "stage", "stages"]


class Field:
    """A 2-D field on a regular grid: ``heights_m[ix, iy]`` (NaN = not
    measured), spacing ``dx_m`` along axis 0 and ``dy_m`` along axis 1
    (``dy_m`` defaults to ``dx_m``)."""

    __slots__ = ("heights_m", "dx_m", "dy_m")

    def __init__(self, heights_m: Any, dx_m: float, dy_m: Optional[float] = None):
        heights = np.ascontiguousarray(heights_m, dtype=np.float64)
        if heights.ndim != 2:
            raise ValueError(f"Field: heights_m must be 2-D, got {heights.ndim}-D")
        self.heights_m = heights
        self.dx_m = float(dx_m)
        self.dy_m = float(dx_m if dy_m is None else dy_m)

    @property
    def shape(self):
        return self.heights_m.shape

    def __repr__(self) -> str:
        nx, ny = self.shape
        return f"Field({nx} x {ny}, dx_m={self.dx_m!r}, dy_m={self.dy_m!r})"


class Files:
    """Named files a stage writes (``name -> bytes``) and, when the output
    declares one, their ``index`` table (which file holds what)."""

    __slots__ = ("files", "index")

    def __init__(self, files: Dict[str, bytes], index: Optional[pl.DataFrame] = None):
        self.files = dict(files)
        self.index = index

    def __repr__(self) -> str:
        return f"Files({sorted(self.files)!r}, index={'yes' if self.index is not None else 'no'})"


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


def _parquet_bytes(frame: pl.DataFrame) -> bytes:
    buffer = io.BytesIO()
    frame.write_parquet(buffer)
    return buffer.getvalue()


def _to_product(name: str, value: Any):
    if isinstance(value, Field):
        return ("field", value.heights_m, value.dx_m, value.dy_m)
    if isinstance(value, pl.DataFrame):
        return ("table", _parquet_bytes(value))
    if isinstance(value, Files):
        index = None if value.index is None else _parquet_bytes(value.index)
        return ("files", {str(k): bytes(v) for k, v in value.files.items()}, index)
    raise ValueError(
        f"input `{name}`: expected a polars DataFrame, a Field or Files, "
        f"got {type(value).__name__}"
    )


def _flatten_inputs(inputs: Dict[str, Any], prefix: str = "") -> Dict[str, Any]:
    """Labelled inputs (``{"responses": {"T1": df}}``) as the stage sees them:
    ``responses.T1``."""
    flat = {}
    for name, value in inputs.items():
        key = f"{prefix}{name}"
        if isinstance(value, dict):
            flat.update(_flatten_inputs(value, key + "."))
        else:
            flat[key] = _to_product(key, value)
    return flat


def _from_product(product):
    tag = product[0]
    if tag == "table":
        return pl.read_parquet(io.BytesIO(product[1]))
    if tag == "field":
        return Field(product[1], product[2], product[3])
    files, index = product[1], product[2]
    return Files(files, None if index is None else pl.read_parquet(io.BytesIO(index)))


def _json_default(value: Any):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if hasattr(value, "__fspath__"):
        return str(value.__fspath__())
    raise TypeError(f"{type(value).__name__} is not a parameter value")


def stage(kind: str, inputs: Optional[Dict[str, Any]] = None, **params: Any) -> Dict[str, Any]:
    """Runs stage ``kind`` on ``inputs`` (name -> DataFrame, Field or Files;
    a dict of them for a labelled input) with ``params`` as in a pipeline's
    ``with:`` block; returns output name -> DataFrame, Field or Files.
    Relative paths resolve against the current directory. A refused
    parameter or input raises ``ValueError`` with the CLI's message."""
    try:
        params_json = json.dumps(params, default=_json_default, allow_nan=False)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{kind}: parameters: {e}") from None
    products = _flatten_inputs(inputs or {})
    outputs = _hypercontact.run_stage(kind, products, params_json)
    return {name: _from_product(p) for name, p in outputs.items()}


def _attribute(kind: str) -> str:
    name = kind.replace("-", "_")
    return name + "_" if keyword.iskeyword(name) else name


def _default_text(param: Dict[str, Any]) -> str:
    if param.get("required"):
        return "(required)"
    default = param.get("default")
    return "-" if default is None else json.dumps(default)


def _docstring(decl: Dict[str, Any]) -> str:
    lines = [decl["summary"], ""]
    if decl["doc"]:
        lines += [decl["doc"], ""]
    if decl["params"]:
        lines.append("Parameters (keyword, as in the pipeline's `with:` block):")
        for p in decl["params"]:
            unit = f" [{p['unit']}]" if p.get("unit") else ""
            lines.append(f"    {p['name']} = {_default_text(p)}{unit}: {p['doc']}")
        lines.append("")
    if decl["inputs"]:
        lines.append("Inputs (keyword):")
        for i in decl["inputs"]:
            lines.append(f"    {i['name']} ({i['kind']}, {i['arity']}): {i['doc']}")
        lines.append("")
    lines.append("Returns " + (
        "the output" if len(decl["outputs"]) == 1 else "a dict of the outputs") + ":")
    for o in decl["outputs"]:
        lines.append(f"    {o['name']} ({o['kind']}): {o['doc']}")
    return "\n".join(lines)


def _signature(decl: Dict[str, Any]) -> inspect.Signature:
    keyword_only = inspect.Parameter.KEYWORD_ONLY
    parameters = [inspect.Parameter(i["name"], keyword_only, default=None) for i in decl["inputs"]]
    taken = {i["name"] for i in decl["inputs"]}
    for p in decl["params"]:
        if p["name"] in taken or not p["name"].isidentifier():
            continue
        default = inspect.Parameter.empty if p.get("required") else p.get("default")
        parameters.append(inspect.Parameter(p["name"], keyword_only, default=default))
    return inspect.Signature(parameters)


def _stage_function(kind: str):
    decl = describe(kind)
    input_names = [i["name"] for i in decl["inputs"]]
    single = decl["outputs"][0]["name"] if len(decl["outputs"]) == 1 else None

    def call(**kwargs: Any):
        inputs = {n: kwargs.pop(n) for n in input_names if kwargs.get(n) is not None}
        for n in input_names:
            kwargs.pop(n, None)
        outputs = stage(kind, inputs, **kwargs)
        return outputs[single] if single is not None else outputs

    call.__name__ = call.__qualname__ = _attribute(kind)
    call.__doc__ = _docstring(decl)
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
