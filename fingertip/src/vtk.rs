//! Deformed-mesh export as legacy ASCII VTK (unstructured grid of tetrahedra), readable by
//! ParaView and VisIt: deformed points, displacement and nodal pressure as point data.

use std::io::Write;

use crate::assembly::State;
use crate::mesh::Mesh;

/// Write the mesh at `state` to `out`.
pub fn write(mesh: &Mesh, state: &State, out: &mut impl Write) -> std::io::Result<()> {
    writeln!(out, "# vtk DataFile Version 3.0")?;
    writeln!(out, "tactile fingertip FE, deformed configuration (m)")?;
    writeln!(out, "ASCII\nDATASET UNSTRUCTURED_GRID")?;
    writeln!(out, "POINTS {} double", mesh.nodes.len())?;
    for x in &state.x {
        writeln!(out, "{:.9e} {:.9e} {:.9e}", x[0], x[1], x[2])?;
    }
    writeln!(out, "CELLS {} {}", mesh.tets.len(), 5 * mesh.tets.len())?;
    for t in &mesh.tets {
        writeln!(out, "4 {} {} {} {}", t[0], t[1], t[2], t[3])?;
    }
    writeln!(out, "CELL_TYPES {}", mesh.tets.len())?;
    for _ in &mesh.tets {
        writeln!(out, "10")?;
    }
    writeln!(out, "POINT_DATA {}", mesh.nodes.len())?;
    writeln!(out, "VECTORS displacement_m double")?;
    for (x, x0) in state.x.iter().zip(&mesh.nodes) {
        writeln!(
            out,
            "{:.9e} {:.9e} {:.9e}",
            x[0] - x0[0],
            x[1] - x0[1],
            x[2] - x0[2]
        )?;
    }
    writeln!(out, "SCALARS pressure_pa double 1\nLOOKUP_TABLE default")?;
    for p in &state.p {
        writeln!(out, "{p:.6e}")?;
    }
    writeln!(out, "SCALARS inclusion int 1\nLOOKUP_TABLE default")?;
    for &i in &mesh.in_inclusion {
        writeln!(out, "{}", u8::from(i))?;
    }
    Ok(())
}
