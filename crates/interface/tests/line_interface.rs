//! Line interfaces (LINE_INTER4, LINE_INTER6): the 2D counterparts of
//! INTER8 / INTER16 between the edges of plane cells.
//!
//! 1. Constant jump: a straight, oblique line of length `L` and thickness
//!    `t` opened by a uniform jump carries the resultant `K delta L t`
//!    along the jump, and the frame is `e1` along the line, `e2 = e_z`,
//!    `e3 = e1 x e_z` (the right of the line); every rule, both shapes.
//! 2. Axisymmetric: the same on a ring: the resultant is `K delta` times
//!    the ring's area `2 pi int r dl` (a line along the axis at radius
//!    `r0`: `2 pi r0 L`; a radial line from `r1` to `r2`: `pi (r2^2 -
//!    r1^2)`).
//! 3. Stiffness: symmetric, positive semi-definite, with exactly the
//!    in-plane rigid modes of the node pairs as null space (rank `2 m`);
//!    the x and y rows do not couple to z, and the element tells that it
//!    uses x and y only.
//! 4. Tangent against central differences of the internal force, small and
//!    finite kinematics (a rotation of 50 degrees in the plane), with the
//!    bilinear mixed-mode law elastic, softening and failed.

use junta_core::element::{ElementContext, PlaneWidth, StepInfo};
use junta_core::law::InterfaceLaw;
use junta_core::registry::{find, ElementBuild, ElementEntry, LawEntry};
use junta_core::topology::CellShape;
use junta_core::{Element, Kinematics};
use junta_interface::element::{InterfaceElement, InterfaceRule};
use junta_interface::LinearPenalty;
use nalgebra::DMatrix;
use std::sync::Arc;

type V3 = [f64; 3];
const SHAPES: [CellShape; 2] = [CellShape::LineInter4, CellShape::LineInter6];
const RULES: [InterfaceRule; 2] = [InterfaceRule::Gauss, InterfaceRule::Lobatto];

/// A straight line from `a` to `b` (ends then middle), doubled.
fn line(shape: CellShape, a: V3, b: V3) -> Vec<V3> {
    let mut side = vec![a, b];
    if shape == CellShape::LineInter6 {
        side.push([0, 1, 2].map(|c| 0.5 * (a[c] + b[c])));
    }
    let mut all = side.clone();
    all.extend(side);
    all
}

fn element(
    shape: CellShape,
    rule: InterfaceRule,
    law: Arc<dyn InterfaceLaw>,
    w: PlaneWidth,
) -> InterfaceElement {
    InterfaceElement::new(shape, rule, law)
        .unwrap()
        .with_line_width(w)
        .unwrap()
}

fn ctx<'a>(coords: &'a [V3], disp: &'a [f64], state: &'a [f64]) -> ElementContext<'a> {
    ElementContext {
        coords,
        disp,
        state_committed: state,
        step: StepInfo {
            exact_tangent: true,
            ..StepInfo::at(2, 1.0, 0.5)
        },
        law_responses: None,
        temperature: None,
    }
}

fn initial_state(el: &InterfaceElement) -> Vec<f64> {
    let mut s = vec![0.0; el.state_len()];
    el.init_state(&mut s);
    s
}

fn compute(
    el: &InterfaceElement,
    coords: &[V3],
    disp: &[f64],
    state: &[f64],
) -> (Vec<f64>, DMatrix<f64>) {
    let n = disp.len();
    let (mut f, mut k, mut trial) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; el.state_len()]);
    el.compute(&ctx(coords, disp, state), &mut trial, &mut f, Some(&mut k))
        .unwrap();
    (f, DMatrix::from_row_slice(n, n, &k))
}

/// The top side moved by `delta` (global), the bottom fixed.
fn opened(coords: &[V3], delta: V3) -> Vec<f64> {
    let m = coords.len() / 2;
    (0..2 * m)
        .flat_map(|a| if a < m { [0.0; 3] } else { delta })
        .collect()
}

/// The resultant on the top side.
fn top_resultant(f: &[f64]) -> V3 {
    let m = f.len() / 6;
    [0, 1, 2].map(|c| (m..2 * m).map(|a| f[3 * a + c]).sum())
}

#[test]
fn constant_jump_carries_k_delta_times_the_area() {
    let k = 1e4;
    let (a, b): (V3, V3) = ([0.3, -0.2, 0.0], [2.7, 1.6, 0.0]);
    let len = ((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1])).sqrt();
    let e1 = [(b[0] - a[0]) / len, (b[1] - a[1]) / len, 0.0];
    let e3 = [e1[1], -e1[0], 0.0];
    for shape in SHAPES {
        for rule in RULES {
            let el = element(
                shape,
                rule,
                Arc::new(LinearPenalty::new([k; 3]).unwrap()),
                PlaneWidth::Thickness(0.4),
            );
            let coords = line(shape, a, b);
            let delta = [
                1e-3 * e3[0] + 2e-4 * e1[0],
                1e-3 * e3[1] + 2e-4 * e1[1],
                0.0,
            ];
            let disp = opened(&coords, delta);
            let s = initial_state(&el);
            let (f, _) = compute(&el, &coords, &disp, &s);
            let r = top_resultant(&f);
            for c in 0..3 {
                let want = k * delta[c] * len * 0.4;
                assert!(
                    (r[c] - want).abs() < 1e-12 * k * len,
                    "{shape:?} {rule:?}: {r:?}"
                );
            }
            for p in el.point_outputs(&ctx(&coords, &disp, &s)).unwrap() {
                let fr = p.get("frame").unwrap();
                let jump = p.get("jump").unwrap();
                for c in 0..3 {
                    assert!((fr[c] - e1[c]).abs() < 1e-14);
                    assert!((fr[3 + c] - [0.0, 0.0, 1.0][c]).abs() < 1e-14);
                    assert!((fr[6 + c] - e3[c]).abs() < 1e-14);
                }
                assert!(
                    (jump[0] - 2e-4).abs() < 1e-15
                        && jump[1].abs() < 1e-15
                        && (jump[2] - 1e-3).abs() < 1e-15
                );
            }
        }
    }
}

#[test]
fn axisymmetric_ring_carries_k_delta_times_the_ring_area() {
    let k = 1e4;
    let pi = std::f64::consts::PI;
    // a line along the axis at r0 = 1.5 (length 2) and a radial one r = 0.5..2.5
    let cases = [
        ([1.5, 0.0, 0.0], [1.5, 2.0, 0.0], 2.0 * pi * 1.5 * 2.0),
        (
            [2.5, 1.0, 0.0],
            [0.5, 1.0, 0.0],
            pi * (2.5f64.powi(2) - 0.25),
        ),
    ];
    for shape in SHAPES {
        for rule in RULES {
            for (a, b, area) in cases {
                let el = element(
                    shape,
                    rule,
                    Arc::new(LinearPenalty::new([k; 3]).unwrap()),
                    PlaneWidth::Axisymmetric,
                );
                let coords = line(shape, a, b);
                let disp = opened(&coords, [3e-4, -1e-3, 0.0]);
                let (f, _) = compute(&el, &coords, &disp, &initial_state(&el));
                let r = top_resultant(&f);
                // a linear line interface with 2 Lobatto points integrates r exactly too
                assert!(
                    (r[0] - k * 3e-4 * area).abs() < 1e-10 * k * area,
                    "{shape:?} {rule:?} {r:?} {area}"
                );
                assert!(
                    (r[1] + k * 1e-3 * area).abs() < 1e-10 * k * area,
                    "{shape:?} {rule:?} {r:?}"
                );
            }
        }
    }
}

/// Under nlgeom an axisymmetric line along the axis at r0 = 1.5, moved
/// out to r = 1.9 (both faces) and opened radially by `delta` (the top
/// face further out by `delta`), carries `K delta` over the ring at its
/// current mid-line radius: `2 pi (1.9 + delta / 2) L`, not the reference
/// ring's `2 pi 1.5 L`.
#[test]
fn axisymmetric_ring_under_nlgeom_carries_k_delta_times_its_current_area() {
    let (k, delta, length) = (1e4, 2e-3, 2.0);
    for shape in SHAPES {
        for rule in RULES {
            let el = element(
                shape,
                rule,
                Arc::new(LinearPenalty::new([k; 3]).unwrap()),
                PlaneWidth::Axisymmetric,
            )
            .with_kinematics(Kinematics::Finite);
            let coords = line(shape, [1.5, 0.0, 0.0], [1.5, length, 0.0]);
            let m = coords.len() / 2;
            let disp: Vec<f64> = (0..2 * m)
                .flat_map(|a| [0.4 + if a >= m { delta } else { 0.0 }, 0.0, 0.0])
                .collect();
            let (f, _) = compute(&el, &coords, &disp, &initial_state(&el));
            let area = std::f64::consts::TAU * (1.9 + 0.5 * delta) * length;
            let r = top_resultant(&f);
            // the line's right-hand normal points towards -x: the top face
            // moved out is a closing jump of -delta along it
            assert!(
                (r[0].abs() - k * delta * area).abs() < 1e-10 * k * delta * area,
                "{shape:?} {rule:?} {r:?} against {}",
                k * delta * area
            );
            assert!(r[1].abs() < 1e-9 * k * delta * area, "{r:?}");
        }
    }
}

#[test]
fn stiffness_is_symmetric_semidefinite_with_the_rigid_modes_of_the_pairs() {
    for shape in SHAPES {
        for rule in RULES {
            let el = element(
                shape,
                rule,
                Arc::new(LinearPenalty::new([2e3, 1e3, 5e3]).unwrap()),
                PlaneWidth::Thickness(1.0),
            );
            let coords = line(shape, [0.0, 0.0, 0.0], [1.0, 0.4, 0.0]);
            let zero = vec![0.0; 3 * coords.len()];
            let (_, k) = compute(&el, &coords, &zero, &initial_state(&el));
            // x-y rows do not couple to z (the model gives z no equation)
            for i in (0..k.nrows()).filter(|i| i % 3 != 2) {
                for j in (2..k.ncols()).step_by(3) {
                    assert_eq!(k[(i, j)], 0.0, "{shape:?}: ({i}, {j})");
                }
            }
            let ids: Vec<usize> = (0..k.nrows()).filter(|i| i % 3 != 2).collect();
            let kp = DMatrix::from_fn(ids.len(), ids.len(), |i, j| k[(ids[i], ids[j])]);
            assert!((&kp - kp.transpose()).amax() < 1e-12 * kp.amax());
            let ev = kp.symmetric_eigen().eigenvalues;
            let top = ev.amax();
            assert!(ev.iter().all(|&v| v > -1e-12 * top));
            let rank = ev.iter().filter(|&&v| v > 1e-10 * top).count();
            assert_eq!(rank, 2 * (coords.len() / 2), "{shape:?} {rule:?}");
            assert_eq!(el.active_components(), [true, true, false]);
        }
    }
}

fn bilinear() -> Arc<dyn InterfaceLaw> {
    let t: toml::Table =
        toml::from_str("K = 1e3\nN = 10.0\nS = 12.0\nG_Ic = 4.0\nG_IIc = 6.0\neta = 2.0\n")
            .unwrap();
    (find::<LawEntry>("bilinear").unwrap().build)(&t).unwrap()
}

/// Central differences of the internal force against the tangent, in the
/// elastic, softening and failed regimes of the bilinear law, small and
/// finite kinematics, plane and axisymmetric widths.
#[test]
fn tangent_matches_finite_differences() {
    let (c, s) = (50f64.to_radians().cos(), 50f64.to_radians().sin());
    for shape in SHAPES {
        for rule in RULES {
            for kin in [Kinematics::Small, Kinematics::Finite] {
                for w in [PlaneWidth::Thickness(0.7), PlaneWidth::Axisymmetric] {
                    let el = element(shape, rule, bilinear(), w).with_kinematics(kin);
                    let coords = line(shape, [1.0, 0.2, 0.0], [2.2, 0.9, 0.0]);
                    let state = initial_state(&el);
                    for (regime, size) in [("elastic", 0.002), ("softening", 0.3), ("failed", 3.0)]
                    {
                        let m = coords.len() / 2;
                        // rotate by 50 degrees (finite), open along a mixed direction with a gradient
                        let disp: Vec<f64> = (0..2 * m)
                            .flat_map(|a| {
                                let x = coords[a];
                                let (rx, ry) = if kin == Kinematics::Finite {
                                    (c * x[0] - s * x[1] - x[0], s * x[0] + c * x[1] - x[1])
                                } else {
                                    (0.0, 0.0)
                                };
                                let o = if a >= m {
                                    size * (1.0 + 0.2 * (a - m) as f64)
                                } else {
                                    0.0
                                };
                                [rx + 0.6 * o, ry + 0.8 * o, 0.0]
                            })
                            .collect();
                        let (_, k) = compute(&el, &coords, &disp, &state);
                        let h = 1e-7 * size.max(1e-2);
                        let mut worst: f64 = 0.0;
                        for j in (0..disp.len()).filter(|j| j % 3 != 2) {
                            let (mut up, mut dn) = (disp.clone(), disp.clone());
                            up[j] += h;
                            dn[j] -= h;
                            let (fu, _) = compute(&el, &coords, &up, &state);
                            let (fd, _) = compute(&el, &coords, &dn, &state);
                            for i in 0..disp.len() {
                                worst = worst.max((k[(i, j)] - (fu[i] - fd[i]) / (2.0 * h)).abs());
                            }
                        }
                        let scale = k.amax().max(1e-6);
                        assert!(
                            worst < 1e-5 * scale,
                            "{shape:?} {rule:?} {kin:?} {w:?} {regime}: {worst:e} of {scale:e}"
                        );
                    }
                }
            }
        }
    }
}

/// The registry builds both keys with their options (an axisymmetric line
/// under nlgeom too), and refuses what does not apply: a thickness with
/// `axisymmetric`, a thickness on a surface interface.
#[test]
fn registry_options() {
    let law = bilinear();
    let build = |key: &str, opts: &str, k: Kinematics| {
        let t: toml::Table = toml::from_str(opts).unwrap();
        (find::<ElementEntry>(key).unwrap().build)(&ElementBuild {
            material: None,
            law: Some(law.clone()),
            options: &t,
            kinematics: k,
        })
    };
    let el = build(
        "line_inter6",
        "thickness = 2.0\nintegration = \"lobatto\"",
        Kinematics::Small,
    )
    .unwrap();
    assert_eq!(el.plane_width(), Some(PlaneWidth::Thickness(2.0)));
    assert_eq!(el.num_points(), 3);
    let el = build("line_inter4", "axisymmetric = true", Kinematics::Small).unwrap();
    assert_eq!(el.plane_width(), Some(PlaneWidth::Axisymmetric));
    let e = build(
        "line_inter4",
        "axisymmetric = true\nthickness = 1.0",
        Kinematics::Small,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("full ring"), "{e}");
    let el = build("line_inter4", "axisymmetric = true", Kinematics::Finite).unwrap();
    assert_eq!(el.kinematics(), Kinematics::Finite);
    let e = build("inter8", "thickness = 1.0", Kinematics::Small)
        .unwrap_err()
        .to_string();
    assert!(e.contains("line interfaces only"), "{e}");
}
