//! Integration tests of the plane elements (plane strain, plane stress,
//! axisymmetric): zero-energy modes, constant-strain states reproduced on
//! distorted cells with the closed-form stresses, the plane-stress and
//! plane-strain relations against isotropic elasticity, the tangent under
//! `nlgeom` against finite differences, and the registry.

use junta_core::element::{ElementContext, PlaneWidth, StepInfo};
use junta_core::registry::{self, ElementBuild, ElementEntry};
use junta_core::topology::{CellShape, QUAD9_NODES, TRI6_NODES};
use junta_core::{CoreError, Element, Kinematics, Material};
use junta_elements as _;
use junta_elements::{EngineeringConstants, Isotropic, Orientation, Orthotropic};
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

const E: f64 = 200e3;
const NU: f64 = 0.3;

fn steel() -> Arc<dyn Material> {
    Arc::new(Isotropic::new(E, NU).unwrap())
}

fn ply() -> Arc<dyn Material> {
    Arc::new(
        Orthotropic::new(
            EngineeringConstants {
                e1: 135e3,
                e2: 9e3,
                e3: 8e3,
                nu12: 0.3,
                nu13: 0.28,
                nu23: 0.45,
                g12: 5e3,
                g13: 4.8e3,
                g23: 3.1e3,
            },
            Some(Orientation::rectangular([1.0, 0.5, 0.0], [-0.5, 1.0, 0.0])),
        )
        .unwrap(),
    )
}

fn build(
    key: &str,
    material: Arc<dyn Material>,
    options: &str,
    k: Kinematics,
) -> Result<Arc<dyn Element>, CoreError> {
    let entry = registry::find::<ElementEntry>(key)?;
    let options: toml::Table = toml::from_str(options).unwrap();
    (entry.build)(&ElementBuild {
        material: Some(material),
        law: None,
        options: &options,
        kinematics: k,
    })
}

/// Every plane and axisymmetric solid key, the incompatible-mode
/// quadrilaterals included.
const ALL_KEYS: [&str; 21] = [
    "cpe3", "cpe4", "cpe6", "cpe8", "cpe8r", "cpe9", "cps3", "cps4", "cps6", "cps8", "cps8r",
    "cps9", "cax3", "cax4", "cax6", "cax8", "cax8r", "cax9", "cpe4i", "cps4i", "cax4i",
];

/// A distorted cell of `shape` in the x-y plane at x in [1, 3] (off the
/// axis), straight-edged (mid-side nodes at mid-edges), counter-clockwise.
fn distorted(shape: CellShape) -> Vec<[f64; 3]> {
    let (corners, natural): (Vec<[f64; 2]>, Vec<[f64; 2]>) = match shape {
        CellShape::PlaneTri3 | CellShape::PlaneTri6 => (
            vec![[1.1, 0.2], [2.9, 0.5], [1.6, 2.1]],
            TRI6_NODES[..shape.num_nodes()].to_vec(),
        ),
        _ => (
            vec![[1.0, 0.1], [2.8, 0.3], [3.0, 2.2], [1.2, 1.7]],
            QUAD9_NODES[..shape.num_nodes()].to_vec(),
        ),
    };
    natural
        .iter()
        .map(|&[r, s]| {
            let p = if corners.len() == 3 {
                let l = [1.0 - r - s, r, s];
                [0, 1].map(|c| (0..3).map(|i| l[i] * corners[i][c]).sum::<f64>())
            } else {
                let w = [
                    (1.0 - r) * (1.0 - s) / 4.0,
                    (1.0 + r) * (1.0 - s) / 4.0,
                    (1.0 + r) * (1.0 + s) / 4.0,
                    (1.0 - r) * (1.0 + s) / 4.0,
                ];
                [0, 1].map(|c| (0..4).map(|i| w[i] * corners[i][c]).sum::<f64>())
            };
            [p[0], p[1], 0.0]
        })
        .collect()
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

/// Internal force and tangent, over all 3 n dofs.
fn compute(el: &dyn Element, coords: &[[f64; 3]], disp: &[f64]) -> (DVector<f64>, DMatrix<f64>) {
    let n = 3 * coords.len();
    let (mut f, mut k) = (vec![0.0; n], vec![0.0; n * n]);
    let mut state = vec![0.0; el.state_len()];
    el.compute(&ctx(coords, disp), &mut state, &mut f, Some(&mut k))
        .unwrap();
    (DVector::from_vec(f), DMatrix::from_row_slice(n, n, &k))
}

/// The in-plane (x, y) rows and columns of `k`.
fn in_plane(k: &DMatrix<f64>) -> DMatrix<f64> {
    let ids: Vec<usize> = (0..k.nrows()).filter(|i| i % 3 != 2).collect();
    DMatrix::from_fn(ids.len(), ids.len(), |i, j| k[(ids[i], ids[j])])
}

fn zero_modes(k: &DMatrix<f64>) -> usize {
    let ev = k.clone().symmetric_eigen().eigenvalues;
    let top = ev.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    ev.iter().filter(|v| v.abs() < 1e-9 * top).count()
}

/// Free single elements: plane strain and plane stress have exactly the 3
/// in-plane rigid modes (2 translations, the rotation about z), an
/// axisymmetric ring only the translation along its axis; the reduced
/// 8-node quadrilateral has the one known spurious mode of the 2 x 2 rule
/// on Q8 (non-communicating), the 9-node one would have three (not
/// offered reduced). The z rows and columns are zero.
#[test]
fn zero_energy_modes_of_a_free_element() {
    for key in ALL_KEYS {
        let el = build(key, steel(), "", Kinematics::Small).unwrap();
        let coords = distorted(el.shape());
        let (_, k) = compute(&*el, &coords, &vec![0.0; 3 * coords.len()]);
        for i in (2..k.nrows()).step_by(3) {
            assert!(k.row(i).iter().all(|&v| v == 0.0) && k.column(i).iter().all(|&v| v == 0.0));
        }
        let rigid = if key.starts_with("cax") { 1 } else { 3 };
        let spurious = usize::from(key.ends_with("8r"));
        assert_eq!(zero_modes(&in_plane(&k)), rigid + spurious, "{key}");
        assert!(
            (&k - k.transpose()).amax() <= 1e-12 * k.amax(),
            "{key} not symmetric"
        );
        assert_eq!(el.active_components(), [true, true, false]);
    }
}

/// The closed-form stress of a uniform in-plane strain `e = [exx, eyy,
/// gxy]` (and for axisymmetric cells the hoop strain u_r / r of the field
/// `u_r = exx r`, which equals exx): plane strain `sigma = C eps` with
/// eps_zz = 0; plane stress the reduced stiffness `E / (1 - nu^2)` with
/// `sigma_zz = 0`, `eps_zz = -nu (exx + eyy) / (1 - nu)`.
fn closed_form(key: &str, e: [f64; 3]) -> ([f64; 6], [f64; 6]) {
    let lam = E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let mu = E / (2.0 * (1.0 + NU));
    let [exx, eyy, gxy] = e;
    match &key[..3] {
        "cpe" => {
            let tr = exx + eyy;
            (
                [
                    lam * tr + 2.0 * mu * exx,
                    lam * tr + 2.0 * mu * eyy,
                    lam * tr,
                    mu * gxy,
                    0.0,
                    0.0,
                ],
                [exx, eyy, 0.0, gxy, 0.0, 0.0],
            )
        }
        "cps" => {
            let c = E / (1.0 - NU * NU);
            let ezz = -NU * (exx + eyy) / (1.0 - NU);
            (
                [
                    c * (exx + NU * eyy),
                    c * (eyy + NU * exx),
                    0.0,
                    mu * gxy,
                    0.0,
                    0.0,
                ],
                [exx, eyy, ezz, gxy, 0.0, 0.0],
            )
        }
        _ => {
            // u_r = exx r: the hoop strain is exx too (gxy = 0 for a ring)
            let tr = 2.0 * exx + eyy;
            (
                [
                    lam * tr + 2.0 * mu * exx,
                    lam * tr + 2.0 * mu * eyy,
                    lam * tr + 2.0 * mu * exx,
                    0.0,
                    0.0,
                    0.0,
                ],
                [exx, eyy, exx, 0.0, 0.0, 0.0],
            )
        }
    }
}

/// A uniform strain on a distorted cell (the displacement linear in x, y;
/// axisymmetric `u_r = exx r`, `u_z = eyy z`): every integration point
/// gives the closed-form stress and strain, and the internal forces are
/// self-equilibrated in x and y (plane cells: the traction of a uniform
/// stress on the boundary sums to zero).
#[test]
fn uniform_strain_gives_the_closed_form_stress_at_every_point() {
    let e = [1.2e-3, -0.7e-3, 0.9e-3];
    for key in ALL_KEYS {
        let el = build(key, steel(), "thickness = 2.5", Kinematics::Small)
            .or_else(|_| build(key, steel(), "", Kinematics::Small))
            .unwrap();
        let coords = distorted(el.shape());
        let axi = key.starts_with("cax");
        let disp: Vec<f64> = coords
            .iter()
            .flat_map(|x| {
                if axi {
                    [e[0] * x[0], e[1] * x[1], 0.0]
                } else {
                    [e[0] * x[0] + e[2] * x[1], e[1] * x[1], 0.0]
                }
            })
            .collect();
        let (want_s, want_e) = closed_form(key, e);
        for p in el.point_outputs(&ctx(&coords, &disp)).unwrap() {
            let (s, st) = (p.get("stress").unwrap(), p.get("strain").unwrap());
            for c in 0..6 {
                assert!(
                    (s[c] - want_s[c]).abs() < 1e-9 * E * 1e-3,
                    "{key} stress {c}: {} vs {}",
                    s[c],
                    want_s[c]
                );
                assert!(
                    (st[c] - want_e[c]).abs() < 1e-12,
                    "{key} strain {c}: {} vs {}",
                    st[c],
                    want_e[c]
                );
            }
        }
        if !axi {
            let (f, _) = compute(&*el, &coords, &disp);
            let scale = f.amax();
            for c in 0..2 {
                let sum: f64 = f.iter().skip(c).step_by(3).sum();
                assert!(sum.abs() < 1e-10 * scale, "{key}: force sum {sum}");
            }
        }
    }
}

/// The volume of a cell: its area times the thickness (plane) or the ring
/// volume `2 pi r_c A` (axisymmetric, Pappus, `r_c` the centroid's radius).
#[test]
fn point_volumes_sum_to_the_area_times_the_width() {
    for key in ["cpe4", "cps8", "cax4", "cax8", "cax6", "cpe3"] {
        let opts = if key.starts_with("cax") {
            ""
        } else {
            "thickness = 0.25"
        };
        let el = build(key, steel(), opts, Kinematics::Small).unwrap();
        let coords = distorted(el.shape());
        let zero = vec![0.0; 3 * coords.len()];
        let vol: f64 = el
            .point_outputs(&ctx(&coords, &zero))
            .unwrap()
            .iter()
            .map(|p| p.get("volume").unwrap()[0])
            .sum();
        // corners counter-clockwise: shoelace area and centroid
        let k = el.shape().plane_reference().unwrap().num_corners();
        let (mut a, mut cx) = (0.0, 0.0);
        for i in 0..k {
            let (p, q) = (coords[i], coords[(i + 1) % k]);
            let cr = p[0] * q[1] - q[0] * p[1];
            a += cr / 2.0;
            cx += (p[0] + q[0]) * cr / 6.0;
        }
        let want = if key.starts_with("cax") {
            2.0 * std::f64::consts::PI * cx
        } else {
            0.25 * a
        };
        assert!((vol - want).abs() < 1e-12 * want, "{key}: {vol} vs {want}");
        let w = el.plane_width().unwrap();
        assert_eq!(
            w,
            if key.starts_with("cax") {
                PlaneWidth::Axisymmetric
            } else {
                PlaneWidth::Thickness(0.25)
            }
        );
    }
}

/// Under `nlgeom` the tangent is the derivative of the internal force:
/// central differences at a large displacement (rotations of tens of
/// degrees and stretches of percent), for every key (the incompatible-mode
/// quadrilaterals with their modes solved at each displacement) and an
/// orthotropic material with in-plane axes, within 1e-6 of the largest
/// entry.
#[test]
fn finite_strain_tangent_matches_finite_differences() {
    for key in ALL_KEYS {
        for mat in [steel(), ply()] {
            let el = build(key, mat, "", Kinematics::Finite).unwrap();
            let coords = distorted(el.shape());
            let disp: Vec<f64> = coords
                .iter()
                .enumerate()
                .flat_map(|(i, x)| {
                    let t: f64 = 0.4; // a rotation of 0.4 rad plus a stretch
                    let (c, s) = (t.cos(), t.sin());
                    let y = [1.03 * (c * x[0] - s * x[1]), c * x[1] + s * x[0]];
                    let wiggle = 0.01 * ((i as f64) * 1.7).sin();
                    [y[0] - x[0] + wiggle, y[1] - x[1] - wiggle, 0.0]
                })
                .collect();
            let (_, k) = compute(&*el, &coords, &disp);
            let n = disp.len();
            let h = 1e-6;
            let mut worst: f64 = 0.0;
            for j in (0..n).filter(|j| j % 3 != 2) {
                let (mut up, mut dn) = (disp.clone(), disp.clone());
                up[j] += h;
                dn[j] -= h;
                let (fu, _) = compute(&*el, &coords, &up);
                let (fd, _) = compute(&*el, &coords, &dn);
                for i in 0..n {
                    worst = worst.max((k[(i, j)] - (fu[i] - fd[i]) / (2.0 * h)).abs());
                }
            }
            assert!(
                worst < 1e-6 * k.amax(),
                "{key}: worst {worst:e} of {:e}",
                k.amax()
            );
            assert!(
                (&k - k.transpose()).amax() <= 1e-10 * k.amax(),
                "{key} tangent not symmetric"
            );
        }
    }
}

/// A rigid rotation under `nlgeom` leaves no internal force and no stress
/// (plane strain and plane stress; an axisymmetric ring cannot rotate in
/// its meridian plane rigidly, but a translation along its axis leaves it
/// free of stress too).
#[test]
fn rigid_motions_are_stress_free_under_nlgeom() {
    for key in ALL_KEYS {
        let el = build(key, steel(), "", Kinematics::Finite).unwrap();
        let coords = distorted(el.shape());
        let disp: Vec<f64> = coords
            .iter()
            .flat_map(|x| {
                if key.starts_with("cax") {
                    [0.0, 0.7, 0.0]
                } else {
                    let (c, s) = (1.1f64.cos(), 1.1f64.sin());
                    [
                        c * x[0] - s * x[1] - x[0] + 0.3,
                        s * x[0] + c * x[1] - x[1] - 0.2,
                        0.0,
                    ]
                }
            })
            .collect();
        let (f, _) = compute(&*el, &coords, &disp);
        assert!(f.amax() < 1e-9, "{key}: {}", f.amax());
    }
}

/// Pure bending of one rectangular element (plane stress, length `L`,
/// height `h`, thickness `t`): the consistent nodal couple `F = M / h` at
/// the free end, the other end held in x (and one corner in y). With the
/// incompatible modes the element is exact (Wilson et al. 1973: the
/// quadratic terms of `u_x = -kappa x y`, `u_y = kappa (x^2 + nu y^2) / 2`,
/// `kappa = M / (E I)`, are its modes); the plain bilinear one locks (its
/// end rotation here is 40 % short).
#[test]
fn incompatible_modes_bend_exactly() {
    let (l, h, t, m): (f64, f64, f64, f64) = (2.0, 1.0, 0.5, 10.0);
    let coords = [
        [0.0, -h / 2.0, 0.0],
        [l, -h / 2.0, 0.0],
        [l, h / 2.0, 0.0],
        [0.0, h / 2.0, 0.0],
    ];
    let kappa = m / (E * t * h.powi(3) / 12.0);
    let exact = |x: [f64; 3]| {
        [
            -kappa * x[0] * x[1],
            kappa * (x[0] * x[0] + NU * (x[1] * x[1] - h * h / 4.0)) / 2.0,
        ]
    };
    let tip = |key: &str| -> Vec<[f64; 2]> {
        let el = build(key, steel(), &format!("thickness = {t}"), Kinematics::Small).unwrap();
        let (_, k) = compute(&*el, &coords, &[0.0; 12]);
        // free dofs: node 1 x, y; node 2 x, y; node 3 y
        let free = [3usize, 4, 6, 7, 10];
        let kf = DMatrix::from_fn(5, 5, |i, j| k[(free[i], free[j])]);
        let f = DVector::from_vec(vec![m / h, 0.0, -m / h, 0.0, 0.0]);
        let u = kf.lu().solve(&f).unwrap();
        vec![[u[0], u[1]], [u[2], u[3]], [0.0, u[4]]]
    };
    let nodes = [coords[1], coords[2], coords[3]];
    let exact_u: Vec<[f64; 2]> = nodes.iter().map(|&x| exact(x)).collect();
    let scale = exact_u
        .iter()
        .map(|v| v[0].abs().max(v[1].abs()))
        .fold(0.0, f64::max);
    let got = tip("cps4i");
    for (g, w) in got.iter().zip(&exact_u) {
        for c in 0..2 {
            assert!(
                (g[c] - w[c]).abs() < 1e-10 * scale,
                "cps4i: {got:?} against {exact_u:?}"
            );
        }
    }
    let plain = tip("cps4");
    assert!(
        plain[0][1] < 0.7 * exact_u[0][1],
        "cps4 should lock: {plain:?} against {exact_u:?}"
    );
}

/// A cell held at every node and heated by dT: the strain is zero, so the
/// stress is `-C alpha dT` restricted by the section: plane strain and
/// axisymmetric `-E alpha dT / (1 - 2 nu)` in every normal component (the
/// out-of-plane one too), plane stress `-E alpha dT / (1 - nu)` in the
/// plane and 0 out of it, with the free thickness strain `(1 + nu) / (1 -
/// nu) alpha dT` (Timoshenko & Goodier, Theory of Elasticity, section 150).
#[test]
fn restrained_heated_cells_carry_the_thermal_stress() {
    let alpha = 1.2e-5;
    let dt = 100.0;
    let mat: Arc<dyn Material> = {
        let t: toml::Table =
            toml::from_str(&format!("E = {E}\nnu = {NU}\nalpha = {alpha}")).unwrap();
        (registry::find::<junta_core::registry::MaterialEntry>("isotropic")
            .unwrap()
            .build)(&t)
        .unwrap()
    };
    for key in ALL_KEYS {
        let el = build(key, mat.clone(), "", Kinematics::Small).unwrap();
        let coords = distorted(el.shape());
        let zero = vec![0.0; 3 * coords.len()];
        let temps = vec![dt; coords.len()];
        let c = ElementContext {
            temperature: Some(&temps),
            ..ctx(&coords, &zero)
        };
        for p in el.point_outputs(&c).unwrap() {
            let s = p.get("stress").unwrap();
            let (inplane, out) = match &key[..3] {
                "cps" => (-E * alpha * dt / (1.0 - NU), 0.0),
                _ => (
                    -E * alpha * dt / (1.0 - 2.0 * NU),
                    -E * alpha * dt / (1.0 - 2.0 * NU),
                ),
            };
            for (c, want) in [(0, inplane), (1, inplane), (2, out)] {
                assert!(
                    (s[c] - want).abs() < 1e-9 * inplane.abs(),
                    "{key}: stress {c} {} against {want}",
                    s[c]
                );
            }
            if key.starts_with("cps") {
                let ezz = p.get("strain").unwrap()[2];
                assert!(
                    (ezz - (1.0 + NU) / (1.0 - NU) * alpha * dt).abs() < 1e-12,
                    "{key}: eps_zz {ezz}"
                );
            }
        }
    }
}

/// Mistakes are errors that name what is valid: an axisymmetric element
/// with a thickness, a non-positive thickness, reduced integration on a
/// linear cell, an unknown option; a cell listed clockwise fails the
/// geometry check.
#[test]
fn mistakes_are_reported() {
    let e = build("cax4", steel(), "thickness = 2.0", Kinematics::Small)
        .unwrap_err()
        .to_string();
    assert!(e.contains("full ring"), "{e}");
    let e = build("cpe4", steel(), "thickness = -1.0", Kinematics::Small)
        .unwrap_err()
        .to_string();
    assert!(e.contains("must be positive"), "{e}");
    let e = build(
        "cps4",
        steel(),
        "integration = \"reduced\"",
        Kinematics::Small,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("hourglass"), "{e}");
    let e = build("cpe8", steel(), "width = 1.0", Kinematics::Small)
        .unwrap_err()
        .to_string();
    assert!(e.contains("thickness"), "{e}");
    let el = build("cpe4", steel(), "", Kinematics::Small).unwrap();
    let mut coords = distorted(CellShape::PlaneQuad4);
    coords.swap(1, 3);
    assert!(el.check_geometry(&coords).is_err());
}
