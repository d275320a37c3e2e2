#!/usr/bin/env python3
"""Peer cross-check of the fingertip FE model: the linear-elastic force-indentation curve of
the same hemisphere, computed independently with gmsh (geometry + tetrahedral mesh) and
scikit-fem (quadratic P2 tetrahedra).

Problem: solid hemisphere of radius R, base z = 0 bonded (all displacement components zero),
the chip package as a rigid box |x|, |y| <= w, 0 <= z <= h cut out of the gel with its faces
fixed, pressed by a rigid frictionless flat (the rod as a platen) at z = R - d. Small-strain
linear elasticity. Contact is exact: an active set of surface dofs whose vertical displacement
is prescribed to the flat, updated until no active dof pulls and no free dof penetrates
(the Rust model uses a penalty instead: an independent check of that choice too).

Prints the mesh, one "force <travel_mm> <force_N>" line per travel, "wall_s <seconds>" and
"cpu_s <seconds>" (meshing + assembly + all solves; CPU time of all threads, since the shared
machine's load inflates wall time) for the bench in fingertip/benches/fe_bench.rs.
"""

import argparse
import sys
import time

import numpy as np


def mesh_hemisphere(radius, w, h, size, pole_size):
    import gmsh

    gmsh.initialize(["-noenv"])
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("hemisphere")
    occ = gmsh.model.occ
    ball = occ.addSphere(0, 0, 0, radius)
    lower = occ.addBox(-2 * radius, -2 * radius, -2 * radius, 4 * radius, 4 * radius, 2 * radius)
    inclusion = occ.addBox(-w, -w, -1e-3 * radius, 2 * w, 2 * w, h + 1e-3 * radius)
    occ.cut([(3, ball)], [(3, lower), (3, inclusion)])
    occ.synchronize()
    # Finer under the contact (around the pole) and at the package.
    dist = gmsh.model.mesh.field.add("Distance")
    pole = occ.addPoint(0, 0, radius)
    chip = occ.addPoint(0, 0, 0)
    occ.synchronize()
    gmsh.model.mesh.field.setNumbers(dist, "PointsList", [pole, chip])
    thr = gmsh.model.mesh.field.add("Threshold")
    gmsh.model.mesh.field.setNumber(thr, "InField", dist)
    gmsh.model.mesh.field.setNumber(thr, "SizeMin", pole_size)
    gmsh.model.mesh.field.setNumber(thr, "SizeMax", size)
    gmsh.model.mesh.field.setNumber(thr, "DistMin", 0.3 * radius)
    gmsh.model.mesh.field.setNumber(thr, "DistMax", 0.7 * radius)
    gmsh.model.mesh.field.setAsBackgroundMesh(thr)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.model.mesh.generate(3)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    _, elem_nodes = gmsh.model.mesh.getElementsByType(4)
    gmsh.finalize()
    index = {int(t): i for i, t in enumerate(tags)}
    points = coords.reshape(-1, 3)
    tets = np.array([index[int(t)] for t in elem_nodes]).reshape(-1, 4)
    used = np.unique(tets)
    remap = -np.ones(len(points), dtype=int)
    remap[used] = np.arange(len(used))
    return points[used], remap[tets]


def solve(args):
    import skfem
    from skfem.models.elasticity import lame_parameters, linear_elasticity
    from scipy.sparse.linalg import splu

    radius = args.radius_mm * 1e-3
    w = args.inclusion_half_width_mm * 1e-3
    h = args.inclusion_height_mm * 1e-3
    size = args.mesh_mm * 1e-3
    pole = (args.pole_mm if args.pole_mm else 0.5 * args.mesh_mm) * 1e-3
    pts, tets = mesh_hemisphere(radius, w, h, size, pole)
    mesh = skfem.MeshTet(pts.T.copy(), tets.T.copy())
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTetP2()))
    lam, mu = lame_parameters(args.youngs_modulus, args.poisson)
    K = linear_elasticity(lam, mu).assemble(basis).tocsr()
    print(f"peer mesh {args.mesh_mm} mm (pole {pole * 1e3:g} mm): {mesh.t.shape[1]} tets, {mesh.p.shape[1]} vertices, {K.shape[0]} P2 dofs")

    x = basis.doflocs  # (3, ndofs): location of every dof
    tol = 1e-9 * radius
    r_of = np.linalg.norm(x, axis=0)
    on_base = np.abs(x[2]) < tol
    in_box = (np.abs(x[0]) <= w + tol) & (np.abs(x[1]) <= w + tol) & (x[2] <= h + tol)
    fixed = np.flatnonzero(on_base | in_box)
    # The z-component dofs on the spherical surface (chords of the sphere: |x| ~ R).
    comp = np.zeros(K.shape[0], dtype=int)
    comp[basis.nodal_dofs[2]] = 1
    if basis.edge_dofs.size:
        comp[basis.edge_dofs[2]] = 1
    boundary = np.zeros(K.shape[0], dtype=bool)
    boundary[basis.get_dofs(mesh.boundary_facets()).flatten()] = True
    surface_z = np.flatnonzero(boundary & (comp == 1) & (r_of > 0.9 * radius) & ~on_base & ~in_box)

    forces = []
    active = set()
    for d_mm in args.travels_mm:
        d = d_mm * 1e-3
        plane = radius - d
        for _ in range(50):
            act = np.array(sorted(active), dtype=int)
            prescribed = np.concatenate([fixed, act])
            values = np.zeros(K.shape[0])
            values[act] = plane - x[2, act]
            free = np.setdiff1d(np.arange(K.shape[0]), prescribed)
            rhs = -K[free][:, prescribed] @ values[prescribed]
            u = values.copy()
            u[free] = splu(K[free][:, free].tocsc()).solve(rhs)
            reaction = K @ u
            zc = x[2, surface_z] + u[surface_z]
            penetrating = set(surface_z[zc > plane + 1e-9 * radius].tolist())
            pulling = set(act[reaction[act] > 0].tolist())
            new = (active | penetrating) - pulling
            if new == active:
                break
            active = new
        act = np.array(sorted(active), dtype=int)
        forces.append(-reaction[act].sum())
        print(f"force {d_mm} {forces[-1]:.6f}  ({len(act)} active dofs)", file=sys.stderr)
    return forces


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--radius-mm", type=float, required=True)
    ap.add_argument("--youngs-modulus", type=float, required=True)
    ap.add_argument("--poisson", type=float, required=True)
    ap.add_argument("--mesh-mm", type=float, required=True)
    ap.add_argument("--pole-mm", type=float, default=None, help="element size within 0.3 R of the pole and the chip (default: half of --mesh-mm)")
    ap.add_argument("--inclusion-half-width-mm", type=float, required=True)
    ap.add_argument("--inclusion-height-mm", type=float, required=True)
    ap.add_argument("--travels-mm", type=float, nargs="+", required=True)
    args = ap.parse_args()
    t0 = time.perf_counter()
    c0 = time.process_time()
    forces = solve(args)
    wall = time.perf_counter() - t0
    cpu = time.process_time() - c0
    for d, f in zip(args.travels_mm, forces):
        print(f"force {d} {f:.6f}")
    print(f"wall_s {wall:.3f}")
    print(f"cpu_s {cpu:.3f}")


if __name__ == "__main__":
    main()
