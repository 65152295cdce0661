"""Builds the two small Zygo .datx test files and their references.

Run once, in a throwaway venv (h5py 3.16, SurfaceTopography 1.27.1):

    python3 -m venv /tmp/venv-datx
    /tmp/venv-datx/bin/pip install h5py "SurfaceTopography==1.27.*"
    /tmp/venv-datx/bin/python make_datx.py

No real .datx file was available. The layout follows what the readers of
SurfaceTopography (IO/DATX.py) and prysm expect of files written by
Zygo Mx: a /MetaData table of (Source, Link, Destination) strings leading from
Root -> Measurement -> Surface -> Path to the height dataset (rows of constant
y); on the dataset, the attributes Unit, No Data and X/Y/Z Converter, each a
one-element array (converters: compound of Category, BaseUnit, Parameters,
with the pixel size in metres as Parameters[1]); instrument attributes under
/Attributes. The references are what SurfaceTopography reads from these
files (in metres, axis 0 = x, NaN = missing), so the Rust reader is checked
against an independent reader of the same bytes, not against this script.

datx-1: vlen strings, f64 heights in nm, chunked + gzip, a No Data value.
datx-2: fixed-length (64-byte) strings, f32 heights in µm, contiguous, NaN for missing
        points and no No Data attribute.
plain.h5: an HDF5 file with one dataset and nothing of a .datx.
"""

import json

import h5py
import numpy as np
import SurfaceTopography

NX, NY = 17, 13
DX_M, DY_M = 0.8e-6, 1.25e-6


def heights():
    """A smooth tilted bump plus a pseudo-random roughness, rows of constant y."""
    y, x = np.mgrid[0:NY, 0:NX]
    rng = np.random.default_rng(17)
    return 40.0 * np.exp(-((x - 8) ** 2 + (y - 5) ** 2) / 18.0) + 0.7 * x - 0.3 * y + rng.normal(0, 2.0, (NY, NX))


def write(path, *, vlen, dtype, unit, unit_scale, no_data, compress):
    if vlen:
        text = h5py.string_dtype("ascii")
    else:
        text = "S64"

    def strings(*values):
        return np.array([v.encode("ascii") for v in values], dtype=text)

    converter = np.dtype([("Category", text), ("BaseUnit", text), ("Parameters", "<f8", (4,))])
    z = heights() * unit_scale
    surface_name = "{5C2F2C0E-6E1A-4B7A-9A0B-3D1E7C9F0A11}"
    path_in_file = f"/Data/Surface/{surface_name}"
    with h5py.File(path, "w") as f:
        rows = [
            ("Root", "Measurement", "{A1}"),
            ("Root", "Version", "1.0"),
            ("{A1}", "Surface", "{B2}"),
            ("{A1}", "Attributes", "{C3}"),
            ("{B2}", "Path", path_in_file),
            ("{C3}", "Path", "/Attributes/{D4}"),
        ]
        meta = np.array(
            [tuple(s.encode("ascii") for s in row) for row in rows],
            dtype=[("Source", text), ("Link", text), ("Destination", text)],
        )
        f.create_dataset("MetaData", data=meta)
        data = z.astype(dtype)
        missing = [(0, 0), (3, 7), (12, 16), (6, 2), (9, 11)]
        for r, c in missing:
            data[r, c] = no_data if no_data is not None else np.nan
        kwargs = dict(chunks=(7, 9), compression="gzip", compression_opts=4) if compress else {}
        ds = f.create_dataset(path_in_file, data=data, **kwargs)
        ds.attrs["Unit"] = strings(unit)
        if no_data is not None:
            ds.attrs["No Data"] = np.array([no_data], dtype=dtype)
        for axis, pixel in (("X", DX_M), ("Y", DY_M)):
            ds.attrs[f"{axis} Converter"] = np.array(
                [(b"LateralCat", b"Pixels", [0.0, pixel, 0.0, 0.0])], dtype=converter
            )
        ds.attrs["Z Converter"] = np.array(
            [(b"HeightCat", unit.encode("ascii"), [0.0, 632.8e-9, 0.5, 1.0])], dtype=converter
        )
        attributes = f.create_group("/Attributes/{D4}")
        attributes.attrs["Data Context.Data Attributes.System Type"] = strings("NewView 9000")
        attributes.attrs["Data Context.Data Attributes.System Serial Number"] = strings("12345678")


def reference(path, stem):
    t = SurfaceTopography.open_topography(path).topography().to_unit("m")
    h = np.ma.filled(t.heights().astype(float), np.nan) if np.ma.is_masked(t.heights()) else t.heights()
    np.save(f"{stem}_m.npy", np.asarray(h, dtype=np.float64))
    dx, dy = t.pixel_size
    return {"shape": list(h.shape), "dx_m": dx, "dy_m": dy, "nan_count": int(np.isnan(h).sum()),
            "instrument": t.info.get("instrument", {})}


write("datx-1.datx", vlen=True, dtype="<f8", unit="NanoMeters", unit_scale=1.0,
      no_data=1.7976931348623157e308, compress=True)
write("datx-2.datx", vlen=False, dtype="<f4", unit="MicroMeters", unit_scale=1e-3,
      no_data=None, compress=False)
# an HDF5 file that is not a .datx, for the reader's refusal
with h5py.File("plain.h5", "w") as f:
    f.create_dataset("heights", data=heights())
index = {stem: reference(f"{stem}.datx", stem) for stem in ("datx-1", "datx-2")}
with open("datx-index.json", "w") as f:
    json.dump(index, f, indent=1)
print(json.dumps(index, indent=1))
