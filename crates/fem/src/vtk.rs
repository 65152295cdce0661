//! The deformed mesh as a legacy-format ASCII VTK unstructured grid
//! (Kitware, "VTK File Formats", the `# vtk DataFile Version 3.0` layout),
//! which ParaView opens: hexahedra (cell type 12) at the deformed node
//! positions, with the displacement vector, the nodal contact pressure and
//! the contact flag as point data (pressure and flag 0 below the top).
//! Every lattice point is written: on a laterally coarsened mesh the unused
//! ones are points no cell references (at their undeformed place), and
//! hanging nodes are ordinary points at their interpolated positions.

use std::io::Write;

use crate::FemError;
use crate::mesh::Mesh;

/// VTK's cell type of the 8-node hexahedron.
const VTK_HEXAHEDRON: u8 = 12;

/// Writes `mesh` displaced by `displacement_m` with the top's contact
/// `pressure_pa` and `contact` flags (per map point, `i * ny + j`).
pub fn write_deformed(
    out: &mut impl Write,
    mesh: &Mesh,
    displacement_m: &[[f64; 3]],
    pressure_pa: &[f64],
    contact: &[bool],
    title: &str,
) -> Result<(), FemError> {
    let n = mesh.nodes_m.len();
    let points = mesh.nx * mesh.ny;
    if displacement_m.len() != n || pressure_pa.len() != points || contact.len() != points {
        return Err(FemError::Io(format!(
            "{} displacements, {} pressures and {} contact flags for {n} nodes and {points} top \
             points",
            displacement_m.len(),
            pressure_pa.len(),
            contact.len()
        )));
    }
    let io = |e: std::io::Error| FemError::Io(e.to_string());
    write_grid(out, mesh, displacement_m, title).map_err(io)?;
    write_top_fields(out, mesh, pressure_pa, contact).map_err(io)
}

/// The header, the displaced nodes, the hexahedra and the displacements.
fn write_grid(
    out: &mut impl Write,
    mesh: &Mesh,
    displacement_m: &[[f64; 3]],
    title: &str,
) -> std::io::Result<()> {
    // The title is one line of at most 256 characters.
    let title: String = title
        .chars()
        .filter(|c| *c != '\n' && *c != '\r')
        .take(255)
        .collect();
    writeln!(
        out,
        "# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET UNSTRUCTURED_GRID"
    )?;
    writeln!(out, "POINTS {} double", mesh.nodes_m.len())?;
    for (x, u) in mesh.nodes_m.iter().zip(displacement_m) {
        writeln!(out, "{:e} {:e} {:e}", x[0] + u[0], x[1] + u[1], x[2] + u[2])?;
    }
    let cells = mesh.elements.len();
    writeln!(out, "CELLS {cells} {}", 9 * cells)?;
    for element in &mesh.elements {
        let nodes: Vec<String> = element.iter().map(usize::to_string).collect();
        writeln!(out, "8 {}", nodes.join(" "))?;
    }
    writeln!(out, "CELL_TYPES {cells}")?;
    for _ in 0..cells {
        writeln!(out, "{VTK_HEXAHEDRON}")?;
    }
    writeln!(out, "POINT_DATA {}", mesh.nodes_m.len())?;
    writeln!(out, "VECTORS displacement_m double")?;
    for u in displacement_m {
        writeln!(out, "{:e} {:e} {:e}", u[0], u[1], u[2])?;
    }
    Ok(())
}

/// The contact pressure and flags of the top's map points, zero on the
/// other nodes.
fn write_top_fields(
    out: &mut impl Write,
    mesh: &Mesh,
    pressure_pa: &[f64],
    contact: &[bool],
) -> std::io::Result<()> {
    let top_point = |node: usize| {
        let (i, j, k) = mesh.grid_of(node);
        (k == mesh.layers).then_some(i * mesh.ny + j)
    };
    writeln!(
        out,
        "SCALARS contact_pressure_pa double 1\nLOOKUP_TABLE default"
    )?;
    for node in 0..mesh.nodes_m.len() {
        writeln!(out, "{:e}", top_point(node).map_or(0.0, |p| pressure_pa[p]))?;
    }
    writeln!(out, "SCALARS contact int 1\nLOOKUP_TABLE default")?;
    for node in 0..mesh.nodes_m.len() {
        writeln!(
            out,
            "{}",
            u8::from(top_point(node).is_some_and(|p| contact[p]))
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{HeightMap, MeshOptions};

    #[test]
    fn writes_a_readable_grid() {
        let h = [0.0, 1e-6, 2e-6, 0.0];
        let map = HeightMap {
            heights_m: &h,
            nx: 2,
            ny: 2,
            dx_m: 1e-5,
            dy_m: 1e-5,
        };
        let mesh = Mesh::new(
            &map,
            &MeshOptions {
                layers: 1,
                ..Default::default()
            },
        )
        .unwrap();
        let u = vec![[0.0, 0.0, -1e-7]; 8];
        let mut text = Vec::new();
        write_deformed(
            &mut text,
            &mesh,
            &u,
            &[1.0e5, 0.0, 0.0, 2.0e5],
            &[true, false, false, true],
            "t",
        )
        .unwrap();
        let text = String::from_utf8(text).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "# vtk DataFile Version 3.0");
        assert_eq!(lines[4], "POINTS 8 double");
        assert!(text.contains("CELLS 1 9\n8 0 2 3 1 4 6 7 5\n"), "{text}");
        assert!(text.contains("CELL_TYPES 1\n12\n"));
        // Top node (0, 0) is node 4: pressure 1e5, in contact.
        let pressures = text.split("LOOKUP_TABLE default\n").nth(1).unwrap();
        assert_eq!(pressures.lines().nth(4), Some("1e5"));
        let flags = text.split("LOOKUP_TABLE default\n").nth(2).unwrap();
        assert_eq!(
            flags.lines().take(8).collect::<Vec<_>>(),
            ["0", "0", "0", "0", "1", "0", "0", "1"]
        );
        assert!(
            write_deformed(&mut Vec::new(), &mesh, &u[..3], &[0.0; 4], &[false; 4], "").is_err()
        );
    }
}
