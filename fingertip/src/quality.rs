//! Mesh-quality report: dihedral angles, aspect ratio, volume against the exact hemisphere.

use crate::mesh::Mesh;

/// Summary of a mesh's element shapes.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct QualityReport {
    /// Number of nodes.
    pub nodes: usize,
    /// Number of tetrahedra.
    pub tets: usize,
    /// Smallest dihedral angle over all elements, degrees (regular tet: 70.5°).
    pub min_dihedral_deg: f64,
    /// Largest dihedral angle over all elements, degrees.
    pub max_dihedral_deg: f64,
    /// Worst aspect ratio: longest edge over (2 sqrt 6 x inradius); 1 for a regular tet.
    pub max_aspect_ratio: f64,
    /// Sum of element volumes over the exact 2/3 pi R^3 (below 1: chords cut the sphere).
    pub volume_ratio: f64,
    /// Smallest element volume, m^3 (positive means no inverted element).
    pub min_volume_m3: f64,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Dihedral angles (degrees) at the six edges of a tetrahedron.
pub fn dihedral_angles_deg(p: [[f64; 3]; 4]) -> [f64; 6] {
    // Outward face normals; face f is opposite vertex f.
    let faces = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    let n: Vec<[f64; 3]> = faces
        .iter()
        .map(|f| {
            let m = cross(sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]]));
            let l = norm(m);
            [m[0] / l, m[1] / l, m[2] / l]
        })
        .collect();
    // The edge between faces i and j; the interior dihedral is pi minus the normals' angle.
    let pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
    pairs.map(|(i, j)| 180.0 - dot(n[i], n[j]).clamp(-1.0, 1.0).acos().to_degrees())
}

fn aspect_ratio(p: [[f64; 3]; 4], volume: f64) -> f64 {
    let faces = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    let area: f64 = faces
        .iter()
        .map(|f| 0.5 * norm(cross(sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]]))))
        .sum();
    let inradius = 3.0 * volume / area;
    let mut longest: f64 = 0.0;
    for i in 0..4 {
        for j in i + 1..4 {
            longest = longest.max(norm(sub(p[i], p[j])));
        }
    }
    longest / (2.0 * 6f64.sqrt() * inradius)
}

/// Measure the mesh.
pub fn report(mesh: &Mesh) -> QualityReport {
    let mut q = QualityReport {
        nodes: mesh.nodes.len(),
        tets: mesh.tets.len(),
        min_dihedral_deg: 180.0,
        max_dihedral_deg: 0.0,
        max_aspect_ratio: 0.0,
        volume_ratio: 0.0,
        min_volume_m3: f64::INFINITY,
    };
    let mut volume = 0.0;
    for (e, t) in mesh.tets.iter().enumerate() {
        let p = t.map(|v| mesh.nodes[v]);
        let v = mesh.tet_volume(e);
        volume += v;
        q.min_volume_m3 = q.min_volume_m3.min(v);
        for a in dihedral_angles_deg(p) {
            q.min_dihedral_deg = q.min_dihedral_deg.min(a);
            q.max_dihedral_deg = q.max_dihedral_deg.max(a);
        }
        q.max_aspect_ratio = q.max_aspect_ratio.max(aspect_ratio(p, v));
    }
    q.volume_ratio = volume / (2.0 / 3.0 * std::f64::consts::PI * mesh.radius_m.powi(3));
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_tetrahedron_has_the_textbook_dihedral_and_unit_aspect() {
        let p = [
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ];
        let v = (8.0f64 / 3.0).abs();
        for a in dihedral_angles_deg(p) {
            assert!((a - (1.0f64 / 3.0).acos().to_degrees()).abs() < 1e-9);
        }
        assert!((aspect_ratio(p, v) - 1.0).abs() < 1e-9);
    }
}
