//! `hypercontact export` on a real run: a height map with missing points
//! and a BEM's pressure and gap maps come out as `.vti` files whose values,
//! spacing and NaN positions are the run's own `.npy` fields; every table
//! comes out as CSV that reads back (with the `csv` crate) to the Parquet
//! table, units on its second line.

use std::path::Path;

use hypercontact::export::vti::parse_vti;
use hypercontact_core::{ColumnData, Field};

use crate::common::{bin, repo, text};

/// A 40 × 30 map, 5 µm spacing, with three unmeasured points.
fn holey_map() -> Field {
    let values = ndarray::Array2::from_shape_fn((40, 30), |(ix, iy)| {
        if [(3, 4), (39, 0), (17, 29)].contains(&(ix, iy)) {
            f64::NAN
        } else {
            1e-6 * ((ix as f64) * 0.37).sin() + 2e-7 * (iy as f64)
        }
    });
    Field::new(values, 5e-6, 5e-6).unwrap()
}

fn pipeline(dir: &Path) -> std::path::PathBuf {
    let map = dir.join("holes.npy");
    holey_map()
        .write_npy(std::fs::File::create(&map).unwrap())
        .unwrap();
    let sample = repo().join("data/samples/self-affine-256.npy");
    let yaml = format!(
        "name: export\n\
         stages:\n  \
           holes: {{ uses: height-map, with: {{ path: {}, pixel_m: 5.0e-6 }} }}\n  \
           surf: {{ uses: height-map, with: {{ path: {}, pixel_m: 20.0e-6 }} }}\n  \
           patch: {{ uses: crop, inputs: {{ surface: surf }}, with: {{ nx: 32, ny: 24 }} }}\n  \
           epdm: {{ uses: material-preset }}\n  \
           bem:\n    uses: bem\n    inputs: {{ surface: patch.height, material: epdm }}\n    \
             with: {{ steps: 6, max_area_fraction: 0.2, map_fractions: [0.1] }}\n",
        map.display(),
        sample.display()
    );
    let file = dir.join("export.yaml");
    std::fs::write(&file, yaml).unwrap();
    file
}

fn read_field(npy: &Path, dx_m: f64, dy_m: f64) -> Field {
    Field::read_npy(std::fs::File::open(npy).unwrap(), dx_m, dy_m).unwrap()
}

/// The .vti holds the field: same grid, spacing, bits and NaN points.
fn assert_vti_is(vti: &Path, field: &Field, name: &str) {
    let back = parse_vti(&std::fs::read(vti).unwrap()).unwrap();
    assert_eq!(back.name, name, "{}", vti.display());
    let (nx, ny) = field.values.dim();
    assert_eq!((back.nx, back.ny), (nx, ny));
    assert_eq!(back.spacing[..2], [field.dx_m, field.dy_m]);
    assert_eq!(back.origin, [0.0; 3]);
    for iy in 0..ny {
        for ix in 0..nx {
            let (a, b) = (back.values[ix + nx * iy], field.values[[ix, iy]]);
            assert_eq!(a.to_bits(), b.to_bits(), "{} ({ix}, {iy})", vti.display());
        }
    }
}

/// ParaView's reader family reads these files. Checked once by hand
/// (2026-11-27) with VTK 9.7.2 (`pip install vtk` in a throwaway venv,
/// numpy 2.4.6) on the files this test's pipeline exports (the same map,
/// run by the binary into /tmp): `r = vtk.vtkXMLImageDataReader();
/// r.SetFileName(p); r.Update(); img = r.GetOutput()` gave, for
/// holes/height.vti, dims (40, 30, 1), spacing (5e-06, 5e-06, 5e-06),
/// origin (0, 0, 0), array `height [m]`, 1200 values of which 3 NaN, and
/// `vtk_to_numpy(array).reshape(30, 40).T` equal to the .npy with NaN at
/// [3, 4], [17, 29], [39, 0]; for bem/pressure_a0.100.vti, dims (32, 24, 1),
/// spacing 2e-05, array `pressure [Pa]`, equal to the run's .npy (max
/// 2525185.391533733 Pa).
#[test]
fn fields_to_vti_and_tables_to_csv_read_back() {
    let t = tempfile::tempdir().unwrap();
    let file = pipeline(t.path());
    let run_dir = t.path().join("out");
    let ran = bin()
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(&run_dir)
        .output()
        .unwrap();
    assert!(ran.status.success(), "{}", text(&ran));

    let exported = bin()
        .args(["export", "--format", "vtk"])
        .arg(&run_dir)
        .output()
        .unwrap();
    assert!(exported.status.success(), "{}", text(&exported));
    let vtk = run_dir.join("export-vtk");
    // The height map with its holes, at the spacing the grid file gives.
    let holes = holey_map();
    assert_vti_is(&vtk.join("holes/height.vti"), &holes, "height [m]");
    let back = parse_vti(&std::fs::read(vtk.join("holes/height.vti")).unwrap()).unwrap();
    assert_eq!(back.values.iter().filter(|v| v.is_nan()).count(), 3);
    assert!(back.values[3 + 40 * 4].is_nan() && back.values[17 + 40 * 29].is_nan());
    let patch = hypercontact_runner::store::read_field(
        &run_dir.join("patch/height.npy"),
        &run_dir.join("patch/height.grid.json"),
    )
    .unwrap();
    assert_vti_is(&vtk.join("patch/height.vti"), &patch, "height [m]");
    assert_vti_is(
        &vtk.join("patch/mirrored.vti"),
        &{
            hypercontact_runner::store::read_field(
                &run_dir.join("patch/mirrored.npy"),
                &run_dir.join("patch/mirrored.grid.json"),
            )
            .unwrap()
        },
        "height [m]",
    );
    // The BEM's maps, named by their index, at the index's spacing.
    let index =
        hypercontact_io::read_parquet_file(&run_dir.join("bem/contact_maps.parquet")).unwrap();
    assert_eq!(index.n_rows(), 1);
    let (dx, dy) = (index.f64("dx_m").unwrap()[0], index.f64("dy_m").unwrap()[0]);
    assert_eq!((dx, dy), (patch.dx_m, patch.dy_m));
    for (column, name) in [("pressure_file", "pressure [Pa]"), ("gap_file", "gap [m]")] {
        let npy = &index.str(column).unwrap()[0];
        let field = read_field(&run_dir.join("bem").join(npy), dx, dy);
        let vti = vtk.join("bem").join(npy.replace(".npy", ".vti"));
        assert_vti_is(&vti, &field, name);
    }

    let exported = bin()
        .args(["export", "--format", "csv", "--out"])
        .arg(t.path().join("csv"))
        .arg(&run_dir)
        .output()
        .unwrap();
    assert!(exported.status.success(), "{}", text(&exported));
    let mut tables = 0;
    for stage in ["bem", "epdm", "patch", "holes"] {
        for entry in std::fs::read_dir(run_dir.join(stage)).unwrap() {
            let path = entry.unwrap().path();
            let Some(stem) = path
                .file_name()
                .unwrap()
                .to_str()
                .unwrap()
                .strip_suffix(".parquet")
            else {
                continue;
            };
            let csv = t.path().join("csv").join(stage).join(format!("{stem}.csv"));
            assert_csv_is(&csv, &path);
            tables += 1;
        }
    }
    assert!(tables >= 4, "{tables} tables");
    // The units line of the response: the stage's declared units.
    let response = std::fs::read_to_string(t.path().join("csv/bem/response.csv")).unwrap();
    let mut lines = response.lines();
    let names: Vec<&str> = lines.next().unwrap().split(',').collect();
    let units: Vec<&str> = lines.next().unwrap().split(',').collect();
    let unit = |c: &str| units[names.iter().position(|n| *n == c).unwrap()];
    assert_eq!(
        (unit("load_n"), unit("z_m"), unit("area_fraction")),
        ("N", "m", "")
    );
}

/// The CSV read with the `csv` crate equals the Parquet table: names,
/// then units (the declared ones), then every cell (floats to the bit).
fn assert_csv_is(csv: &Path, parquet: &Path) {
    let table = hypercontact_io::read_parquet_file(parquet).unwrap();
    let meta =
        hypercontact_io::parquet_columns_meta(std::fs::File::open(parquet).unwrap()).unwrap();
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_path(csv)
        .unwrap_or_else(|e| panic!("{}: {e}", csv.display()));
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), table.n_rows() + 2, "{}", csv.display());
    assert_eq!(rows[0].iter().collect::<Vec<_>>(), table.column_names());
    for (i, m) in meta.iter().enumerate() {
        if !m.unit.is_empty() {
            assert_eq!(&rows[1][i], m.unit.as_str(), "{} {}", csv.display(), m.name);
        }
    }
    for (c, column) in table.columns().iter().enumerate() {
        for (r, row) in rows[2..].iter().enumerate() {
            let cell = &row[c];
            match &column.data {
                ColumnData::F64(v) => {
                    let back: f64 = cell.parse().unwrap();
                    assert!(
                        back.to_bits() == v[r].to_bits() || (back.is_nan() && v[r].is_nan()),
                        "{} {} row {r}: {cell} vs {}",
                        csv.display(),
                        column.name,
                        v[r]
                    );
                }
                ColumnData::I64(v) => assert_eq!(cell.parse::<i64>().unwrap(), v[r]),
                ColumnData::Str(v) => assert_eq!(cell, v[r].as_str()),
            }
        }
    }
}

/// A folder that holds no run is refused, naming the record it looked for.
#[test]
fn a_folder_without_a_run_is_refused_by_name() {
    let t = tempfile::tempdir().unwrap();
    let out = bin()
        .args(["export", "--format", "csv"])
        .arg(t.path())
        .output()
        .unwrap();
    assert!(!out.status.success());
    let said = text(&out);
    assert!(
        said.contains("provenance.json") && said.contains("runs/<name>"),
        "{said}"
    );
}

/// The tests of `folders`, which `export` refuses `--out` with: a path
/// below a folder by name or through `..`, and the cache around a path
/// found by its marker.
#[test]
fn a_folder_below_another_by_name_or_through_dots() {
    use hypercontact_runner::folders::{is_within, part_within};
    use std::path::PathBuf;
    let root = Path::new("/work/run");
    assert_eq!(
        part_within(Path::new("/work/run/a/../b"), root),
        Some(PathBuf::from("b"))
    );
    assert_eq!(part_within(root, root), Some(PathBuf::new()));
    assert!(!is_within(Path::new("/work/runs"), root));
    assert!(!is_within(Path::new("/work/run/.."), root));
}

#[test]
fn the_cache_around_a_path_is_found_by_its_marker() {
    use hypercontact_runner::cache::MARKER;
    use hypercontact_runner::folders::enclosing_cache;
    let t = tempfile::tempdir().unwrap();
    let cache = t.path().join("c");
    std::fs::create_dir_all(&cache).unwrap();
    std::fs::write(cache.join(MARKER), "").unwrap();
    assert_eq!(
        enclosing_cache(&cache.join("entries/x")),
        Some(cache.clone())
    );
    assert_eq!(enclosing_cache(&cache), Some(cache.clone()));
    assert_eq!(enclosing_cache(&t.path().join("elsewhere")), None);
}
