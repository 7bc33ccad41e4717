//! Helpers shared by the one-point law tests: the central-difference check
//! of a law's tangent and reading a named output from a point's state.

use junta_core::law::{InterfaceLaw, LawResponse};

/// Central differences of the traction against the law's tangent at
/// `jump`, every entry (the nonsymmetric part too), relative to the
/// largest entry of the law's tangent (at least 1): the step is `h_rel`
/// times the largest jump component (at least 1e-9), the tolerance 1e-5.
/// `trial` evaluates the law from the point's committed state (its trial
/// state discarded). Returns the law's tangent.
#[allow(dead_code)]
pub fn check_fd_tangent(
    trial: impl Fn([f64; 3]) -> LawResponse,
    jump: [f64; 3],
    h_rel: f64,
    what: &str,
) -> [[f64; 3]; 3] {
    let r = trial(jump);
    let scale = r
        .tangent
        .iter()
        .flatten()
        .fold(1.0f64, |m, v| m.max(v.abs()));
    let h = h_rel * jump.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-9);
    for j in 0..3 {
        let (mut a, mut b) = (jump, jump);
        a[j] += h;
        b[j] -= h;
        let (ta, tb) = (trial(a).traction, trial(b).traction);
        for i in 0..3 {
            let fd = (ta[i] - tb[i]) / (2.0 * h);
            let err = (fd - r.tangent[i][j]).abs() / scale;
            assert!(
                err < 1e-5,
                "{what}: dt{i}/ddelta{j}: law {:.6e}, finite difference {fd:.6e} (jump {jump:?})",
                r.tangent[i][j]
            );
        }
    }
    r.tangent
}

/// The law's output `name` at a point with the state `state`.
#[allow(dead_code)]
pub fn output_of(law: &dyn InterfaceLaw, state: &[f64], name: &str) -> f64 {
    let names = law.output_names();
    let mut v = vec![0.0; names.len()];
    law.outputs(state, &mut v);
    v[names
        .iter()
        .position(|n| *n == name)
        .unwrap_or_else(|| panic!("law `{}` has no output `{name}`", law.key()))]
}
