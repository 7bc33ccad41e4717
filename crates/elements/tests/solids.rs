//! Integration tests of the solid elements: patch tests on distorted meshes,
//! rigid-body modes and zero-energy-mode counts, tangent checks, a closed
//! form uniaxial case, geometry errors and the registry.

use junta_core::element::{ElementContext, ElementError, StepInfo};
use junta_core::mesh::generate::{box_mesh, BoxSpec};
use junta_core::mesh::Mesh;
use junta_core::registry::{self, ElementBuild, ElementEntry, MaterialEntry};
use junta_core::topology::{CellShape, HEX27_NODES};
use junta_core::{CoreError, Element, Material};
use junta_elements as _;
use junta_elements::{EngineeringConstants, Isotropic, Orientation, Orthotropic};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};
use std::sync::Arc;

// ---------------------------------------------------------------- helpers

/// Small deterministic generator (xorshift64*), values in [-1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (v >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

fn steel() -> Arc<dyn Material> {
    Arc::new(Isotropic::new(210e9, 0.3).unwrap())
}

fn composite() -> Arc<dyn Material> {
    Arc::new(
        Orthotropic::new(
            EngineeringConstants {
                e1: 135e9,
                e2: 9e9,
                e3: 8e9,
                nu12: 0.3,
                nu13: 0.28,
                nu23: 0.45,
                g12: 5e9,
                g13: 4.8e9,
                g23: 3.1e9,
            },
            Some(Orientation::rectangular([1.0, 0.5, 0.2], [-0.3, 1.0, 0.4])),
        )
        .unwrap(),
    )
}

fn build(
    key: &str,
    material: Arc<dyn Material>,
    options: &str,
) -> Result<Arc<dyn Element>, CoreError> {
    let entry = registry::find::<ElementEntry>(key)?;
    let options: toml::Table = toml::from_str(options).unwrap();
    (entry.build)(&ElementBuild {
        material: Some(material),
        law: None,
        options: &options,
        kinematics: Default::default(),
    })
}

fn shape_of(key: &str) -> CellShape {
    registry::find::<ElementEntry>(key).unwrap().shape
}

fn ctx<'a>(coords: &'a [[f64; 3]], disp: &'a [f64]) -> ElementContext<'a> {
    ElementContext {
        coords,
        disp,
        state_committed: &[],
        step: StepInfo::default(),
        law_responses: None,
        temperature: None,
    }
}

/// f_int and K of one element as nalgebra objects.
fn compute(el: &dyn Element, coords: &[[f64; 3]], disp: &[f64]) -> (DVector<f64>, DMatrix<f64>) {
    let n = 3 * el.num_nodes();
    let mut f = vec![0.0; n];
    let mut k = vec![0.0; n * n];
    el.compute(&ctx(coords, disp), &mut [], &mut f, Some(&mut k))
        .unwrap();
    (DVector::from_vec(f), DMatrix::from_row_slice(n, n, &k))
}

fn f_only(el: &dyn Element, coords: &[[f64; 3]], disp: &[f64]) -> DVector<f64> {
    let n = 3 * el.num_nodes();
    let mut f = vec![0.0; n];
    el.compute(&ctx(coords, disp), &mut [], &mut f, None)
        .unwrap();
    DVector::from_vec(f)
}

/// One element on a box `[0, 2] x [0, 1.5] x [0, 1]` with every node
/// (mid-nodes included, so edges are curved) moved randomly.
fn distorted_element(shape: CellShape, seed: u64) -> Vec<[f64; 3]> {
    let mut rng = Rng(seed);
    let size = [2.0, 1.5, 1.0];
    HEX27_NODES[..shape.num_nodes()]
        .iter()
        .map(|xi| {
            let mut x = [0.0; 3];
            for i in 0..3 {
                x[i] = 0.5 * (xi[i] + 1.0) * size[i] + 0.08 * rng.next();
            }
            x
        })
        .collect()
}

/// Trilinear interpolation of the 8 corners at natural point `xi`.
fn trilinear(corners: &[[f64; 3]], xi: [f64; 3]) -> [f64; 3] {
    let mut x = [0.0; 3];
    for (c, p) in corners.iter().zip(HEX27_NODES.iter()) {
        let n = (1.0 + p[0] * xi[0]) * (1.0 + p[1] * xi[1]) * (1.0 + p[2] * xi[2]) / 8.0;
        for i in 0..3 {
            x[i] += n * c[i];
        }
    }
    x
}

/// A `div^3` box mesh of `shape` with every corner node (boundary ones too)
/// moved randomly by up to `amp` times the element size. With `curved`
/// false, the higher-order nodes are put back where the trilinear map of
/// each element's corners puts them (straight edges, mid-nodes at
/// midpoints); with `curved` true they are moved randomly too.
/// Returns the mesh and whether each node lies on the box boundary.
fn distorted_mesh(
    shape: CellShape,
    div: usize,
    amp: f64,
    curved: bool,
    seed: u64,
) -> (Mesh, Vec<bool>) {
    let size = [1.0, 1.2, 0.8];
    let mut mesh = box_mesh(&BoxSpec::new(size, [div; 3], shape), "b", "x", "m").unwrap();
    let mut boundary = vec![false; mesh.nodes.len()];
    for set in mesh.node_sets.values() {
        for &i in set {
            boundary[i] = true;
        }
    }
    let nn = shape.num_nodes();
    let block = mesh.blocks[0].clone();
    let mut is_corner = vec![false; mesh.nodes.len()];
    for e in 0..block.len() {
        for &i in &block.element(e)[..8] {
            is_corner[i] = true;
        }
    }
    let mut rng = Rng(seed);
    for (i, x) in mesh.nodes.iter_mut().enumerate() {
        if is_corner[i] || curved {
            let a = if is_corner[i] { amp } else { 0.3 * amp };
            for d in 0..3 {
                x[d] += a * size[d] / div as f64 * rng.next();
            }
        }
    }
    if !curved {
        for e in 0..block.len() {
            let conn = block.element(e);
            let corners: Vec<[f64; 3]> = conn[..8].iter().map(|&i| mesh.nodes[i]).collect();
            for a in 8..nn {
                mesh.nodes[conn[a]] = trilinear(&corners, HEX27_NODES[a]);
            }
        }
    }
    (mesh, boundary)
}

fn element_coords(mesh: &Mesh, e: usize) -> Vec<[f64; 3]> {
    mesh.blocks[0]
        .element(e)
        .iter()
        .map(|&i| mesh.nodes[i])
        .collect()
}

fn element_disp(mesh: &Mesh, e: usize, u: &DVector<f64>) -> Vec<f64> {
    mesh.blocks[0]
        .element(e)
        .iter()
        .flat_map(|&i| [u[3 * i], u[3 * i + 1], u[3 * i + 2]])
        .collect()
}

/// Dense global stiffness of a one-block mesh.
fn assemble(el: &dyn Element, mesh: &Mesh) -> DMatrix<f64> {
    let ndof = 3 * mesh.nodes.len();
    let mut k = DMatrix::zeros(ndof, ndof);
    let block = &mesh.blocks[0];
    for e in 0..block.len() {
        let coords = element_coords(mesh, e);
        el.check_geometry(&coords).unwrap();
        let (_, ke) = compute(el, &coords, &vec![0.0; 3 * coords.len()]);
        let conn = block.element(e);
        for (a, &ga) in conn.iter().enumerate() {
            for (b, &gb) in conn.iter().enumerate() {
                for i in 0..3 {
                    for j in 0..3 {
                        k[(3 * ga + i, 3 * gb + j)] += ke[(3 * a + i, 3 * b + j)];
                    }
                }
            }
        }
    }
    k
}

/// Number of eigenvalues below `tol` times the largest.
fn zero_modes(k: &DMatrix<f64>, tol: f64) -> (usize, Vec<f64>) {
    let eig = k.clone().symmetric_eigen().eigenvalues;
    let max = eig.iter().fold(0.0f64, |m, &v| m.max(v.abs()));
    let mut sorted: Vec<f64> = eig.iter().map(|v| v / max).collect();
    sorted.sort_by(|a, b| a.partial_cmp(b).unwrap());
    (sorted.iter().filter(|v| v.abs() < tol).count(), sorted)
}

fn voigt_strain(a: &Matrix3<f64>) -> Vector6<f64> {
    Vector6::new(
        a[(0, 0)],
        a[(1, 1)],
        a[(2, 2)],
        a[(0, 1)] + a[(1, 0)],
        a[(1, 2)] + a[(2, 1)],
        a[(2, 0)] + a[(0, 2)],
    )
}

// ---------------------------------------------------------------- patch tests

/// Impose u = A x + c on the boundary nodes, solve for the interior ones,
/// and check interior displacements and every integration-point stress.
/// Returns the worst relative errors (displacement, stress).
fn patch_test(
    key: &str,
    material: Arc<dyn Material>,
    amp: f64,
    curved: bool,
    seed: u64,
) -> (f64, f64) {
    let el = build(key, material.clone(), "").unwrap();
    let (mesh, boundary) = distorted_mesh(el.shape(), 3, amp, curved, seed);
    let k = assemble(el.as_ref(), &mesh);
    let a = Matrix3::new(1.0, 0.3, -0.2, 0.5, -0.7, 0.4, 0.1, 0.6, 0.9) * 1e-3;
    let c0 = Vector3::new(0.01, -0.02, 0.005);
    let exact = |x: [f64; 3]| a * Vector3::from(x) + c0;
    let n = mesh.nodes.len();
    let free: Vec<usize> = (0..3 * n).filter(|&d| !boundary[d / 3]).collect();
    let fixed: Vec<usize> = (0..3 * n).filter(|&d| boundary[d / 3]).collect();
    assert!(!free.is_empty());
    let mut u = DVector::zeros(3 * n);
    for &d in &fixed {
        u[d] = exact(mesh.nodes[d / 3])[d % 3];
    }
    let kff = k.select_rows(&free).select_columns(&free);
    let kfc = k.select_rows(&free).select_columns(&fixed);
    let uc = u.select_rows(&fixed);
    let uf = kff
        .lu()
        .solve(&(-(kfc * uc)))
        .expect("interior stiffness is regular");
    let umax = u.amax();
    let mut err_u: f64 = 0.0;
    for (i, &d) in free.iter().enumerate() {
        u[d] = uf[i];
        err_u = err_u.max((uf[i] - exact(mesh.nodes[d / 3])[d % 3]).abs() / umax);
    }
    let sig_exact = material.elasticity() * voigt_strain(&a);
    let mut err_s: f64 = 0.0;
    for e in 0..mesh.blocks[0].len() {
        let coords = element_coords(&mesh, e);
        let disp = element_disp(&mesh, e, &u);
        let out = el.point_outputs(&ctx(&coords, &disp)).unwrap();
        assert_eq!(out.len(), el.num_points());
        for p in out {
            let s = Vector6::from_column_slice(p.get("stress").unwrap());
            err_s = err_s.max((s - sig_exact).norm() / sig_exact.norm());
        }
    }
    (err_u, err_s)
}

/// For h8i this checks Taylor's `det J0 / det J` scaling of the
/// incompatible modes: without it (measured by switching it off) the same
/// isotropic patch has a displacement error 4.4e-4 and a stress error 19 %.
#[test]
fn patch_test_on_distorted_straight_edged_meshes() {
    for key in ["h8", "h8i", "h20", "h27", "h20r", "h27r"] {
        for (mat, name) in [(steel(), "isotropic"), (composite(), "orthotropic")] {
            let (eu, es) = patch_test(key, mat, 0.2, false, 0x9E37_79B9_7F4A_7C15);
            eprintln!("patch {key} {name}: displacement error {eu:.2e}, stress error {es:.2e}");
            assert!(eu < 1e-10 && es < 1e-10, "{key} {name}: {eu:.2e} {es:.2e}");
        }
    }
}

#[test]
fn patch_test_on_curved_meshes() {
    // Isoparametric elements reproduce linear fields for any geometry; with
    // curved edges the constant-stress equilibrium of the interior nodes is
    // still exact for the full rules (measured here; see the report).
    for key in ["h20", "h27"] {
        let (eu, es) = patch_test(key, steel(), 0.1, true, 12345);
        eprintln!("curved patch {key}: displacement error {eu:.2e}, stress error {es:.2e}");
        assert!(eu < 1e-10 && es < 1e-10, "{key}: {eu:.2e} {es:.2e}");
    }
}

// ---------------------------------------------------------------- rigid-body modes

fn rigid_modes(coords: &[[f64; 3]]) -> Vec<DVector<f64>> {
    let mut modes = Vec::new();
    for t in 0..3 {
        modes.push(DVector::from_iterator(
            3 * coords.len(),
            coords.iter().flat_map(|_| {
                let mut v = [0.0; 3];
                v[t] = 1.0;
                v
            }),
        ));
    }
    for r in 0..3 {
        let mut w = Vector3::zeros();
        w[r] = 1.0;
        modes.push(DVector::from_iterator(
            3 * coords.len(),
            coords.iter().flat_map(|x| {
                let u = w.cross(&Vector3::from(*x));
                [u[0], u[1], u[2]]
            }),
        ));
    }
    modes
}

#[test]
fn rigid_body_motions_give_zero_internal_force() {
    for key in ["h8", "h8i", "h20", "h27", "h20r", "h27r"] {
        for mat in [steel(), composite()] {
            let el = build(key, mat, "").unwrap();
            let coords = distorted_element(el.shape(), 7);
            let (_, k) = compute(el.as_ref(), &coords, &vec![0.0; 3 * coords.len()]);
            for (m, u) in rigid_modes(&coords).iter().enumerate() {
                let f = f_only(el.as_ref(), &coords, u.as_slice());
                let scale = k.amax() * u.amax();
                assert!(
                    f.amax() < 1e-13 * scale,
                    "{key} mode {m}: |f| = {:.3e}",
                    f.amax()
                );
            }
        }
    }
}

#[test]
fn full_integration_has_exactly_six_zero_modes() {
    for key in ["h8", "h8i", "h20", "h27"] {
        for mat in [steel(), composite()] {
            let el = build(key, mat, "").unwrap();
            let coords = distorted_element(el.shape(), 11);
            let (_, k) = compute(el.as_ref(), &coords, &vec![0.0; 3 * coords.len()]);
            assert!(
                (&k - k.transpose()).amax() <= 1e-14 * k.amax(),
                "{key} not symmetric"
            );
            let (zeros, eig) = zero_modes(&k, 1e-10);
            eprintln!(
                "{key}: {zeros} zero eigenvalues; smallest non-zero / largest = {:.2e}",
                eig[zeros]
            );
            assert_eq!(zeros, 6, "{key}: eigenvalues {:?}", &eig[..10]);
            assert!(eig[6] > 1e-6, "{key}: weak mode {:.2e}", eig[6]);
            assert!(eig[0] > -1e-12, "{key}: negative eigenvalue {:.2e}", eig[0]);
        }
    }
}

/// Reduced 2x2x2 integration: 8 points x 6 strains = rank <= 48.
/// Single element: H20r (60 dofs) has 12 zero modes (6 rigid + 6 spurious),
/// H27r (81 dofs) has 33 (6 rigid + 27 spurious). Assembled 2x2x2 blocks:
/// the H20r spurious modes do not propagate (6 zero modes), H27r's do
/// (45 zero modes measured on the 2x2x2 block of 375 dofs).
#[test]
fn reduced_integration_zero_mode_counts() {
    let mut found = Vec::new();
    for key in ["h20r", "h27r"] {
        let el = build(key, steel(), "").unwrap();
        let coords = distorted_element(el.shape(), 11);
        let (_, k) = compute(el.as_ref(), &coords, &vec![0.0; 3 * coords.len()]);
        assert!((&k - k.transpose()).amax() <= 1e-14 * k.amax());
        let (single, eig) = zero_modes(&k, 1e-10);
        assert!(eig[0] > -1e-12);
        assert!(
            eig[single] > 1e-6,
            "{key}: no clear gap above the zero modes: {:.2e}",
            eig[single]
        );
        let (mesh, _) = distorted_mesh(el.shape(), 2, 0.15, false, 99);
        let km = assemble(el.as_ref(), &mesh);
        let (assembled, _) = zero_modes(&km, 1e-10);
        eprintln!("{key}: single element {single} zero modes, 2x2x2 block {assembled}");
        found.push((key, single, assembled));
    }
    assert_eq!(found[0], ("h20r", 12, 6));
    assert_eq!(found[1].1, 33);
    assert_eq!(found[1].2, 45, "h27r spurious modes propagate");
}

// ---------------------------------------------------------------- tangent

#[test]
fn tangent_matches_finite_differences_of_internal_force() {
    let mut rng = Rng(42);
    for key in ["h8", "h8i", "h20", "h27", "h20r", "h27r"] {
        let el = build(key, composite(), "").unwrap();
        let coords = distorted_element(el.shape(), 3);
        let n = 3 * coords.len();
        let u = DVector::from_fn(n, |_, _| 1e-3 * rng.next());
        let v = DVector::from_fn(n, |_, _| rng.next());
        let (f, k) = compute(el.as_ref(), &coords, u.as_slice());
        // f_int = K u (linear elasticity, computed from stresses)
        assert!((&k * &u - &f).amax() <= 1e-12 * f.amax(), "{key}: K u != f");
        let h = 1e-6;
        let fp = f_only(el.as_ref(), &coords, (&u + h * &v).as_slice());
        let fm = f_only(el.as_ref(), &coords, (&u - h * &v).as_slice());
        let fd = (fp - fm) / (2.0 * h);
        let kv = &k * &v;
        assert!(
            (&fd - &kv).amax() <= 1e-7 * kv.amax(),
            "{key}: {:.3e}",
            (&fd - &kv).amax() / kv.amax()
        );
        // compute without the tangent gives the same force
        assert_eq!(f_only(el.as_ref(), &coords, u.as_slice()), f);
    }
}

// ---------------------------------------------------------------- closed form

#[test]
fn unit_cube_h8_under_uniaxial_stress() {
    let (e, nu, sigma) = (70e9, 0.33, 1e6);
    let el = build("h8", Arc::new(Isotropic::new(e, nu).unwrap()), "").unwrap();
    let coords: Vec<[f64; 3]> = HEX27_NODES[..8]
        .iter()
        .map(|p| [0.5 * (p[0] + 1.0), 0.5 * (p[1] + 1.0), 0.5 * (p[2] + 1.0)])
        .collect();
    let (_, k) = compute(el.as_ref(), &coords, &[0.0; 24]);
    // symmetry planes x = 0, y = 0, z = 0; traction sigma on x = 1 (area 1, 4 nodes)
    let mut fixed = Vec::new();
    let mut f = DVector::zeros(24);
    for (a, x) in coords.iter().enumerate() {
        for (d, &xd) in x.iter().enumerate() {
            if xd == 0.0 {
                fixed.push(3 * a + d);
            }
        }
        if x[0] == 1.0 {
            f[3 * a] = sigma / 4.0;
        }
    }
    let free: Vec<usize> = (0..24).filter(|d| !fixed.contains(d)).collect();
    let uf = k
        .select_rows(&free)
        .select_columns(&free)
        .lu()
        .solve(&f.select_rows(&free))
        .unwrap();
    let mut u = vec![0.0; 24];
    for (i, &d) in free.iter().enumerate() {
        u[d] = uf[i];
    }
    for (a, x) in coords.iter().enumerate() {
        let exact = [
            sigma / e * x[0],
            -nu * sigma / e * x[1],
            -nu * sigma / e * x[2],
        ];
        for d in 0..3 {
            assert!(
                (u[3 * a + d] - exact[d]).abs() < 1e-12 * sigma / e,
                "node {a} dof {d}"
            );
        }
    }
    for p in el.point_outputs(&ctx(&coords, &u)).unwrap() {
        let s = p.get("stress").unwrap();
        assert!((s[0] - sigma).abs() < 1e-9 * sigma);
        assert!(s[1..].iter().all(|v| v.abs() < 1e-9 * sigma), "{s:?}");
        let eps = p.get("strain").unwrap();
        assert!((eps[0] - sigma / e).abs() < 1e-12 * sigma / e);
        assert!((eps[1] + nu * sigma / e).abs() < 1e-12 * sigma / e);
        assert!((p.get("mises").unwrap()[0] - sigma).abs() < 1e-9 * sigma);
        assert!(p.position.iter().all(|&c| c > 0.0 && c < 1.0));
    }
}

// ---------------------------------------------------------------- geometry errors

#[test]
fn inverted_element_is_an_error_not_a_panic() {
    for key in ["h8", "h8i", "h20", "h27", "h20r", "h27r"] {
        let el = build(key, steel(), "").unwrap();
        let mut coords = distorted_element(el.shape(), 5);
        el.check_geometry(&coords).unwrap();
        // mirror through z = 0: every det J changes sign
        for x in coords.iter_mut() {
            x[2] = -x[2];
        }
        let e = el.check_geometry(&coords).unwrap_err();
        assert!(
            matches!(e, ElementError::NegativeJacobian { point: 0, det } if det < 0.0),
            "{e}"
        );
        let n = 3 * coords.len();
        let r = el.compute(
            &ctx(&coords, &vec![0.0; n]),
            &mut [],
            &mut vec![0.0; n],
            Some(&mut vec![0.0; n * n]),
        );
        assert!(matches!(r, Err(ElementError::NegativeJacobian { .. })));
        assert!(el.point_outputs(&ctx(&coords, &vec![0.0; n])).is_err());
        // a flat element (all z = 0)
        for x in coords.iter_mut() {
            x[2] = 0.0;
        }
        assert!(matches!(
            el.check_geometry(&coords),
            Err(ElementError::NegativeJacobian { .. })
        ));
    }
}

#[test]
fn midnode_past_the_quarter_point_is_caught_at_the_corner() {
    // H20 on the unit cube with mid-edge node 8 (edge 0-1) at x = 0.2: dx/dxi
    // at corner 0 is 2 m - 1/2 < 0, but every Gauss point is still fine.
    let el = build("h20", steel(), "").unwrap();
    let mut coords: Vec<[f64; 3]> = HEX27_NODES[..20]
        .iter()
        .map(|p| [0.5 * (p[0] + 1.0), 0.5 * (p[1] + 1.0), 0.5 * (p[2] + 1.0)])
        .collect();
    coords[8][0] = 0.2;
    let r = el.compute(&ctx(&coords, &[0.0; 60]), &mut [], &mut [0.0; 60], None);
    assert!(r.is_ok(), "Gauss points should be fine: {r:?}");
    match el.check_geometry(&coords) {
        Err(ElementError::NegativeJacobian { point, det }) => {
            assert_eq!(
                point,
                el.num_points(),
                "corner 0 is reported as num_points + 0"
            );
            assert!(det < 0.0);
        }
        other => panic!("expected NegativeJacobian at corner 0, got {other:?}"),
    }
}

// ---------------------------------------------------------------- registry

#[test]
fn registry_holds_the_elements_and_materials() {
    let elements: Vec<&str> = registry::entries::<ElementEntry>()
        .iter()
        .map(|e| e.key)
        .collect();
    for key in ["h8", "h8i", "h20", "h27", "h20r", "h27r"] {
        assert!(
            elements.contains(&key),
            "missing element {key} in {elements:?}"
        );
    }
    assert!(!elements.contains(&"h8r"));
    let materials: Vec<&str> = registry::entries::<MaterialEntry>()
        .iter()
        .map(|e| e.key)
        .collect();
    for key in ["isotropic", "orthotropic"] {
        assert!(materials.contains(&key), "missing material {key}");
    }
    assert_eq!(shape_of("h8"), CellShape::Hex8);
    assert_eq!(shape_of("h8i"), CellShape::Hex8);
    assert_eq!(shape_of("h20r"), CellShape::Hex20);
    assert_eq!(shape_of("h27r"), CellShape::Hex27);
    for (key, points) in [
        ("h8", 8),
        ("h8i", 8),
        ("h20", 27),
        ("h27", 27),
        ("h20r", 8),
        ("h27r", 8),
    ] {
        let el = build(key, steel(), "").unwrap();
        assert_eq!(
            (el.key(), el.num_points(), el.state_len()),
            (key, points, 0)
        );
    }
}

#[test]
fn registry_builds_from_tables_and_reports_mistakes() {
    let t: toml::Table = toml::from_str("E = 1e9\nnu = 0.2").unwrap();
    let m = (registry::find::<MaterialEntry>("isotropic").unwrap().build)(&t).unwrap();
    assert_eq!(m.key(), "isotropic");
    let t: toml::Table = toml::from_str("E = 1e9\nnu = 0.7").unwrap();
    let e = (registry::find::<MaterialEntry>("isotropic").unwrap().build)(&t).unwrap_err();
    assert!(
        matches!(e, CoreError::InvalidParameters { .. }) && e.to_string().contains("0.5"),
        "{e}"
    );

    let el = build("h20", m.clone(), "integration = \"reduced\"").unwrap();
    assert_eq!((el.key(), el.num_points()), ("h20r", 8));
    let el = build("h27r", m.clone(), "integration = \"reduced\"").unwrap();
    assert_eq!(el.num_points(), 8);
    let e = build("h20r", m.clone(), "integration = \"full\"")
        .unwrap_err()
        .to_string();
    assert!(e.contains("h20"), "{e}");
    let e = build("h8", m.clone(), "integration = \"reduced\"")
        .unwrap_err()
        .to_string();
    assert!(e.contains("h8") && e.contains("full"), "{e}");
    let e = build("h8", m.clone(), "integration = \"half\"")
        .unwrap_err()
        .to_string();
    assert!(e.contains("full") && e.contains("reduced"), "{e}");
    let e = build("h8", m.clone(), "rule = 2").unwrap_err().to_string();
    assert!(e.contains("rule") && e.contains("integration"), "{e}");
    let opts = toml::Table::new();
    let e = (registry::find::<ElementEntry>("h27").unwrap().build)(&ElementBuild {
        material: None,
        law: None,
        options: &opts,
        kinematics: Default::default(),
    })
    .unwrap_err();
    assert!(
        matches!(e, CoreError::InvalidParameters { .. })
            && e.to_string().contains("requires a material"),
        "{e}"
    );
}

// ---------------------------------------------------------------- h8i in bending

/// A prism `[0, L] x [-b/2, b/2] x [-h/2, h/2]` of `nx x 1 x 1` elements
/// of `key` under an end moment `M` about y (consistent nodal forces of
/// `sigma_xx = -M z / I` on the end face: `-+ M / (2 h)` at the upper /
/// lower nodes), with `u_x = 0` on `x = 0` (a plane of antisymmetry of the
/// exact solution) and two more supports against rigid motions. Returns the
/// largest nodal error against the exact solution (relative to the largest
/// displacement), the deflection `w(L) - w(0)` and the largest stress error
/// at the integration points (relative to `M h / (2 I)`).
///
/// Closed form (linear elasticity of a prism in pure bending, curvature
/// `κ = M / (E I)`, origin at the centroid of the root section):
/// `u = -κ x z`, `v = ν κ y z`, `w = κ (x^2 + ν (z^2 - y^2)) / 2`,
/// `sigma_xx = -E κ z`, every other stress zero; the end deflection is
/// `w(L) - w(0) = M L^2 / (2 E I)`.
fn pure_bending(key: &str, nx: usize) -> (f64, f64, f64) {
    let (e, nu) = (70e9, 0.3);
    let (l, b, h, m) = (2.0, 0.5, 0.3, 1.0e4);
    let i = b * h * h * h / 12.0;
    let kappa = m / (e * i);
    let el = build(key, Arc::new(Isotropic::new(e, nu).unwrap()), "").unwrap();
    let mut mesh = box_mesh(
        &BoxSpec::new([l, b, h], [nx, 1, 1], CellShape::Hex8),
        "b",
        key,
        "m",
    )
    .unwrap();
    for x in mesh.nodes.iter_mut() {
        x[1] -= 0.5 * b;
        x[2] -= 0.5 * h;
    }
    let k = assemble(el.as_ref(), &mesh);
    let n = mesh.nodes.len();
    let mut f = DVector::zeros(3 * n);
    for &a in &mesh.node_sets["x1"] {
        f[3 * a] = -mesh.nodes[a][2].signum() * m / (2.0 * h);
    }
    let find = |y: f64, z: f64| {
        mesh.node_sets["x0"]
            .iter()
            .copied()
            .find(|&a| mesh.nodes[a][1] == y && mesh.nodes[a][2] == z)
            .unwrap()
    };
    let (na, nb) = (find(-0.5 * b, -0.5 * h), find(0.5 * b, -0.5 * h));
    let mut fixed: Vec<usize> = mesh.node_sets["x0"].iter().map(|&a| 3 * a).collect();
    fixed.extend([3 * na + 1, 3 * na + 2, 3 * nb + 2]);
    let free: Vec<usize> = (0..3 * n).filter(|d| !fixed.contains(d)).collect();
    let uf = k
        .select_rows(&free)
        .select_columns(&free)
        .lu()
        .solve(&f.select_rows(&free))
        .unwrap();
    let mut u = DVector::zeros(3 * n);
    for (j, &d) in free.iter().enumerate() {
        u[d] = uf[j];
    }
    let exact = |x: [f64; 3]| {
        [
            -kappa * x[0] * x[2],
            nu * kappa * x[1] * x[2],
            0.5 * kappa * (x[0] * x[0] + nu * (x[2] * x[2] - x[1] * x[1])),
        ]
    };
    // the supports fix the solution up to a rigid translation in y and z
    let ea = exact(mesh.nodes[na]);
    let shift = [0.0, u[3 * na + 1] - ea[1], u[3 * na + 2] - ea[2]];
    let umax = u.amax();
    let mut err_u: f64 = 0.0;
    for (a, x) in mesh.nodes.iter().enumerate() {
        let ex = exact(*x);
        for d in 0..3 {
            err_u = err_u.max((u[3 * a + d] - ex[d] - shift[d]).abs() / umax);
        }
    }
    let tip = find(-0.5 * b, -0.5 * h);
    let end = mesh.node_sets["x1"]
        .iter()
        .copied()
        .find(|&a| mesh.nodes[a][1] == -0.5 * b && mesh.nodes[a][2] == -0.5 * h)
        .unwrap();
    let deflection = u[3 * end + 2] - u[3 * tip + 2];
    let smax = m * h / (2.0 * i);
    let mut err_s: f64 = 0.0;
    for ee in 0..mesh.blocks[0].len() {
        let coords = element_coords(&mesh, ee);
        let disp = element_disp(&mesh, ee, &u);
        for p in el.point_outputs(&ctx(&coords, &disp)).unwrap() {
            let s = p.get("stress").unwrap();
            let mut exact_s = [0.0; 6];
            exact_s[0] = -e * kappa * p.position[2];
            for d in 0..6 {
                err_s = err_s.max((s[d] - exact_s[d]).abs() / smax);
            }
        }
    }
    (err_u, deflection, err_s)
}

#[test]
fn h8i_is_exact_in_pure_bending_where_h8_locks() {
    let (e, b, h, l, m) = (70e9, 0.5, 0.3, 2.0, 1.0e4);
    // closed form: w(L) - w(0) = M L^2 / (2 E I)
    let exact = m * l * l / (2.0 * e * b * h * h * h / 12.0);
    for nx in [1, 3] {
        let (eu, w, es) = pure_bending("h8i", nx);
        eprintln!(
            "h8i pure bending {nx}x1x1: deflection {w:.6e} (exact {exact:.6e}), \
             nodal error {eu:.1e}, stress error {es:.1e}"
        );
        assert!(((w - exact) / exact).abs() < 1e-10, "{w} vs {exact}");
        assert!(eu < 1e-10 && es < 1e-10, "{eu:.2e} {es:.2e}");
        // the same mesh of H8 locks
        let (_, w8, _) = pure_bending("h8", nx);
        eprintln!(
            "h8  pure bending {nx}x1x1: deflection {w8:.6e} ({:+.1} %)",
            100.0 * (w8 / exact - 1.0)
        );
        assert!(w8 < 0.5 * exact, "h8 {w8} vs {exact}");
    }
}

// ---------------------------------------------------------------- wedges (C3D6, C3D15)

/// A unit cube of `n^3` cells, each split into two wedges along the
/// diagonal 0-2 of its z-faces, interior corner nodes moved by up to
/// `amp * h` and (if `curved`) interior mid-nodes by `amp * h / 4`.
/// Returns nodes, connectivities (Abaqus order) and boundary flags.
fn wedge_mesh(
    shape: CellShape,
    n: usize,
    amp: f64,
    curved: bool,
    seed: u64,
) -> (Vec<[f64; 3]>, Vec<Vec<usize>>, Vec<bool>) {
    let mut rng = Rng(seed);
    let h = 1.0 / n as f64;
    let on_box = |x: &[f64; 3]| {
        x.iter()
            .any(|&c| c.abs() < 1e-12 || (c - 1.0).abs() < 1e-12)
    };
    let id = |i: usize, j: usize, k: usize| (k * (n + 1) + j) * (n + 1) + i;
    let mut nodes = Vec::new();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let mut x = [i as f64 * h, j as f64 * h, k as f64 * h];
                if !on_box(&x) {
                    for c in x.iter_mut() {
                        *c += amp * h * rng.next();
                    }
                }
                nodes.push(x);
            }
        }
    }
    let mut mids = std::collections::HashMap::new();
    let mut cells = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                for tri in [[0, 1, 2], [0, 2, 3]] {
                    let mut cell: Vec<usize> = tri
                        .iter()
                        .map(|&a| c[a])
                        .chain(tri.iter().map(|&a| c[a + 4]))
                        .collect();
                    if shape == CellShape::Wedge15 {
                        let edges = [
                            (0, 1),
                            (1, 2),
                            (2, 0),
                            (3, 4),
                            (4, 5),
                            (5, 3),
                            (0, 3),
                            (1, 4),
                            (2, 5),
                        ];
                        for (a, b) in edges {
                            let (p, q) = (cell[a].min(cell[b]), cell[a].max(cell[b]));
                            let m = *mids.entry((p, q)).or_insert_with(|| {
                                let mut x = [0.0; 3];
                                for (d, xd) in x.iter_mut().enumerate() {
                                    *xd = 0.5 * (nodes[p][d] + nodes[q][d]);
                                }
                                if curved && !on_box(&x) {
                                    for xd in x.iter_mut() {
                                        *xd += 0.25 * amp * h * rng.next();
                                    }
                                }
                                nodes.push(x);
                                nodes.len() - 1
                            });
                            cell.push(m);
                        }
                    }
                    cells.push(cell);
                }
            }
        }
    }
    let boundary = nodes.iter().map(on_box).collect();
    (nodes, cells, boundary)
}

/// Patch test on a wedge mesh: `u = A x + c` imposed on the boundary,
/// interior solved; returns worst relative errors (displacement, stress).
fn wedge_patch_test(key: &str, material: Arc<dyn Material>, curved: bool) -> (f64, f64) {
    let el = build(key, material.clone(), "").unwrap();
    let (nodes, cells, boundary) = wedge_mesh(el.shape(), 3, 0.2, curved, 5);
    let n = nodes.len();
    let mut k = DMatrix::<f64>::zeros(3 * n, 3 * n);
    for cell in &cells {
        let coords: Vec<[f64; 3]> = cell.iter().map(|&a| nodes[a]).collect();
        el.check_geometry(&coords).unwrap();
        let (_, ke) = compute(el.as_ref(), &coords, &vec![0.0; 3 * cell.len()]);
        for (a, &ga) in cell.iter().enumerate() {
            for (b, &gb) in cell.iter().enumerate() {
                for i in 0..3 {
                    for j in 0..3 {
                        k[(3 * ga + i, 3 * gb + j)] += ke[(3 * a + i, 3 * b + j)];
                    }
                }
            }
        }
    }
    let a = Matrix3::new(1.0, 0.3, -0.2, 0.5, -0.7, 0.4, 0.1, 0.6, 0.9) * 1e-3;
    let c0 = Vector3::new(0.01, -0.02, 0.005);
    let exact = |x: [f64; 3]| a * Vector3::from(x) + c0;
    let free: Vec<usize> = (0..3 * n).filter(|&d| !boundary[d / 3]).collect();
    let fixed: Vec<usize> = (0..3 * n).filter(|&d| boundary[d / 3]).collect();
    assert!(!free.is_empty());
    let mut u = DVector::<f64>::zeros(3 * n);
    for &d in &fixed {
        u[d] = exact(nodes[d / 3])[d % 3];
    }
    let kff = k.select_rows(&free).select_columns(&free);
    let kfc = k.select_rows(&free).select_columns(&fixed);
    let uf = kff
        .lu()
        .solve(&(-(kfc * u.select_rows(&fixed))))
        .expect("interior stiffness is regular");
    let umax = u.amax();
    let mut err_u: f64 = 0.0;
    for (i, &d) in free.iter().enumerate() {
        u[d] = uf[i];
        err_u = err_u.max((uf[i] - exact(nodes[d / 3])[d % 3]).abs() / umax);
    }
    let sig_exact = material.elasticity() * voigt_strain(&a);
    let mut err_s: f64 = 0.0;
    for cell in &cells {
        let coords: Vec<[f64; 3]> = cell.iter().map(|&a| nodes[a]).collect();
        let disp: Vec<f64> = cell
            .iter()
            .flat_map(|&a| [u[3 * a], u[3 * a + 1], u[3 * a + 2]])
            .collect();
        let out = el.point_outputs(&ctx(&coords, &disp)).unwrap();
        assert_eq!(out.len(), el.num_points());
        for p in out {
            let s = Vector6::from_column_slice(p.get("stress").unwrap());
            err_s = err_s.max((s - sig_exact).norm() / sig_exact.norm());
        }
    }
    (err_u, err_s)
}

#[test]
fn wedge_patch_tests_on_distorted_meshes() {
    for key in ["wedge6", "wedge6r", "wedge15"] {
        for curved in [false, true] {
            if key != "wedge15" && curved {
                continue;
            }
            for (mat, name) in [(steel(), "isotropic"), (composite(), "orthotropic")] {
                let (eu, es) = wedge_patch_test(key, mat, curved);
                eprintln!("{key} {name} curved={curved}: |du| {eu:.2e}, |dsigma| {es:.2e}");
                if curved {
                    // Curved wedge15 edges: the 9-point rule (CalculiX's) does not
                    // integrate cof(J) dN exactly, so the patch is passed only up to
                    // the rule's error (measured 4.3e-5 / 2.8e-3 with mid-nodes moved
                    // by h/20); straight-edged distorted meshes pass to round-off.
                    assert!(eu < 1e-4 && es < 1e-2, "{key} {name}: {eu:.2e} {es:.2e}");
                } else {
                    assert!(eu < 1e-10 && es < 1e-10, "{key} {name}: {eu:.2e} {es:.2e}");
                }
            }
        }
    }
}

/// One distorted wedge (corners moved, mid-nodes off the midpoints).
fn distorted_wedge(shape: CellShape, seed: u64) -> Vec<[f64; 3]> {
    let mut rng = Rng(seed);
    junta_core::topology::WEDGE15_NODES[..shape.num_nodes()]
        .iter()
        .map(|p| {
            [
                2.0 * p[0] + 0.15 * rng.next(),
                1.5 * p[1] + 0.15 * rng.next(),
                0.5 * p[2] + 0.1 * rng.next(),
            ]
        })
        .collect()
}

#[test]
fn wedges_rigid_modes_and_six_zero_eigenvalues() {
    for key in ["wedge6", "wedge6r", "wedge15"] {
        for mat in [steel(), composite()] {
            let el = build(key, mat, "").unwrap();
            let coords = distorted_wedge(el.shape(), 3);
            el.check_geometry(&coords).unwrap();
            let (_, k) = compute(el.as_ref(), &coords, &vec![0.0; 3 * coords.len()]);
            assert!(
                (&k - k.transpose()).amax() <= 1e-14 * k.amax(),
                "{key} not symmetric"
            );
            for (m, u) in rigid_modes(&coords).iter().enumerate() {
                let f = f_only(el.as_ref(), &coords, u.as_slice());
                assert!(
                    f.amax() < 1e-13 * k.amax() * u.amax(),
                    "{key} mode {m}: {:.3e}",
                    f.amax()
                );
            }
            let (zeros, eig) = zero_modes(&k, 1e-10);
            eprintln!("{key}: {zeros} zero eigenvalues; next {:.2e}", eig[zeros]);
            if key == "wedge6r" {
                // CalculiX's 2-point C3D6 rule: 12 strain samples, one spurious mode
                assert_eq!(zeros, 7, "{key}: eigenvalues {:?}", &eig[..10]);
                continue;
            }
            assert_eq!(zeros, 6, "{key}: eigenvalues {:?}", &eig[..10]);
            assert!(eig[6] > 1e-6 && eig[0] > -1e-12, "{key}: {:?}", &eig[..8]);
        }
    }
}

/// Volume check against the closed form: a right prism on the triangle
/// (0,0), (2,0), (0,1.5) of height 1 has volume 1.5; a uniaxial stress
/// sigma_zz = E eps needs total axial force sigma * area on the top face.
#[test]
fn wedge_uniaxial_force_equals_stress_times_area() {
    for key in ["wedge6", "wedge6r", "wedge15"] {
        let el = build(key, Arc::new(Isotropic::new(1000.0, 0.0).unwrap()), "").unwrap();
        let coords: Vec<[f64; 3]> = junta_core::topology::WEDGE15_NODES[..el.num_nodes()]
            .iter()
            .map(|p| [2.0 * p[0], 1.5 * p[1], 0.5 * (p[2] + 1.0)])
            .collect();
        // u_z = 0.01 z: sigma_zz = 10 (nu = 0), area 1.5: force 15 on the top
        let disp: Vec<f64> = coords
            .iter()
            .flat_map(|x| [0.0, 0.0, 0.01 * x[2]])
            .collect();
        let f = f_only(el.as_ref(), &coords, &disp);
        let top: f64 = coords
            .iter()
            .enumerate()
            .filter(|(_, x)| x[2] > 0.99)
            .map(|(a, _)| f[3 * a + 2])
            .sum();
        assert!((top - 15.0).abs() < 1e-12, "{key}: top force {top}");
    }
}

/// A one-element mesh of `shape` with `coords`.
fn one_element_mesh(shape: CellShape, coords: Vec<[f64; 3]>) -> Mesh {
    let n = coords.len();
    Mesh {
        nodes: coords,
        blocks: vec![junta_core::mesh::ElementBlock {
            name: "w".into(),
            shape,
            connectivity: (0..n).collect(),
            element_type: shape.name().into(),
            material: "m".into(),
        }],
        ..Default::default()
    }
}

/// Pressure on wedge faces S1..S5 (face_load.rs). Closed forms on the
/// right prism over the triangle (0,0), (2,0), (0,1.5), height 1: each
/// face's resultant is `-p A n` (outward n: S1 -z, A 1.5; S2 +z, 1.5; S3
/// -y, 2; S4 (0.6, 0.8, 0), 2.5; S5 -x, 1.5); the consistent nodal shares
/// of a flat face (`int N_a dA`): Tri3 A/3 per corner; Tri6 0 per corner,
/// A/3 per mid-edge; Q4 A/4 per corner; Q8 -A/12 per corner, A/3 per
/// mid-side. On a distorted (curved-face) wedge the five faces close: the
/// forces sum to zero (every face outward, integration exact). S6 does not
/// exist on a wedge: an error naming it.
#[test]
fn pressure_on_wedge_faces() {
    use junta_core::mesh::FaceRef;
    use junta_elements::face_load::{add_face_load, FaceLoad};
    let p = 7.0;
    let normals: [([f64; 3], f64); 5] = [
        ([0.0, 0.0, -1.0], 1.5),
        ([0.0, 0.0, 1.0], 1.5),
        ([0.0, -1.0, 0.0], 2.0),
        ([0.6, 0.8, 0.0], 2.5),
        ([-1.0, 0.0, 0.0], 1.5),
    ];
    for shape in [CellShape::Wedge6, CellShape::Wedge15] {
        let coords: Vec<[f64; 3]> = junta_core::topology::WEDGE15_NODES[..shape.num_nodes()]
            .iter()
            .map(|x| [2.0 * x[0], 1.5 * x[1], 0.5 * (x[2] + 1.0)])
            .collect();
        let mesh = one_element_mesh(shape, coords);
        for (face, &(n, area)) in normals.iter().enumerate() {
            let mut f = vec![0.0; 3 * mesh.nodes.len()];
            let r = FaceRef {
                block: 0,
                element: 0,
                face,
            };
            add_face_load(&mesh, &[r], FaceLoad::Pressure(p), &mut f).unwrap();
            let nodes = mesh.face_nodes(r);
            let fshape = shape.face_shape_of(face).unwrap();
            let corners = fshape.num_corners();
            for (k, &a) in nodes.iter().enumerate() {
                let share = match (fshape, k < corners) {
                    (CellShape::Tri3, _) => 1.0 / 3.0,
                    (CellShape::Tri6, true) => 0.0,
                    (CellShape::Tri6, false) => 1.0 / 3.0,
                    (CellShape::Quad4, _) => 0.25,
                    (CellShape::Quad8, true) => -1.0 / 12.0,
                    (CellShape::Quad8, false) => 1.0 / 3.0,
                    s => panic!("{s:?}"),
                };
                for c in 0..3 {
                    let want = -p * area * share * n[c];
                    assert!(
                        (f[3 * a + c] - want).abs() < 1e-13,
                        "{shape:?} S{} node {a}: {} vs {want}",
                        face + 1,
                        f[3 * a + c]
                    );
                }
            }
            // nothing on the other nodes
            for a in (0..mesh.nodes.len()).filter(|a| !nodes.contains(a)) {
                assert!(f[3 * a..3 * a + 3].iter().all(|v| *v == 0.0));
            }
        }
        // distorted wedge: a closed surface
        let mesh = one_element_mesh(shape, distorted_wedge(shape, 11));
        let all: Vec<FaceRef> = (0..5)
            .map(|face| FaceRef {
                block: 0,
                element: 0,
                face,
            })
            .collect();
        let mut f = vec![0.0; 3 * mesh.nodes.len()];
        add_face_load(&mesh, &all, FaceLoad::Pressure(p), &mut f).unwrap();
        let mut one = vec![0.0; 3 * mesh.nodes.len()];
        add_face_load(&mesh, &all[1..2], FaceLoad::Pressure(p), &mut one).unwrap();
        let scale = one.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for c in 0..3 {
            let s: f64 = f.iter().skip(c).step_by(3).sum();
            assert!(s.abs() < 1e-13 * scale, "{shape:?}: sum {s}");
        }
        // a face the wedge does not have
        let e = add_face_load(
            &mesh,
            &[FaceRef {
                block: 0,
                element: 0,
                face: 5,
            }],
            FaceLoad::Pressure(p),
            &mut f,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("S1..S5") && e.contains("S6"), "{e}");
    }
}
