//! Memory estimates made before anything large is allocated: a box with a
//! billion elements, a model whose matrix would not fit, a sweep with a
//! hundred million values fail at once with the estimate against what the
//! machine has, naming the key.

use crate::error::{bail, Result};
use junta_core::mesh::Mesh;

/// Memory the machine can give (`MemAvailable` of `/proc/meminfo`, else
/// `MemTotal`), in bytes; `None` where unknown (then only the address
/// space bounds the estimate). `JUNTA_MEMORY_LIMIT` (bytes) overrides it.
pub fn machine_memory() -> Option<f64> {
    if let Some(v) = std::env::var("JUNTA_MEMORY_LIMIT")
        .ok()
        .and_then(|s| s.trim().parse::<f64>().ok())
    {
        return Some(v);
    }
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let field = |name: &str| {
        text.lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse::<f64>().ok())
            .map(|kib| kib * 1024.0)
    };
    field("MemAvailable:").or_else(|| field("MemTotal:"))
}

/// The process's peak resident memory so far (`VmHWM` of
/// `/proc/self/status`), bytes; `None` where unknown.
pub fn peak_resident_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = text.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

fn gb(bytes: f64) -> String {
    format!("{:.3} GB", bytes / 1e9)
}

/// Fail when `bytes` (an estimate for `what`) exceeds the machine's memory
/// (or the address space).
pub fn check_memory(what: &str, bytes: f64) -> Result<()> {
    if !bytes.is_finite() || bytes > isize::MAX as f64 {
        bail!(
            "{what} needs about {} (more than any machine can address)",
            gb(bytes)
        );
    }
    if let Some(avail) = machine_memory() {
        if bytes > avail {
            bail!(
                "{what} needs about {}, the machine has {} available",
                gb(bytes),
                gb(avail)
            );
        }
    }
    Ok(())
}

/// Estimated bytes of a generated box with `divisions` elements per axis,
/// `order` 1 or 2: its mesh (coordinates, labels, connectivity) and the
/// model built on it (as [`model_bytes`]).
pub fn box_bytes(divisions: [usize; 3], order: usize, nodes_per_element: usize) -> f64 {
    let d = divisions.map(|n| n as f64);
    let nodes: f64 = d.iter().map(|&n| order as f64 * n + 1.0).product();
    let elements: f64 = d.iter().product();
    let k = 3.0 * nodes_per_element as f64;
    let mesh = nodes * (24.0 + 8.0 + 16.0) + elements * nodes_per_element as f64 * 8.0;
    mesh + 3.0 * nodes * 8.0 * 12.0 + (3.0 * nodes + elements * k * k / 2.0) * 12.0
}

/// Estimated bytes of a model built on `mesh`: the dof map and vectors,
/// element state, and the assembled tangent (upper triangle, values and
/// column indices: sum over elements of (3 n)^2 / 2 entries, which
/// undercounts the shared entries of a conforming mesh by less than 2x).
pub fn model_bytes(mesh: &Mesh) -> f64 {
    let dofs = 3.0 * mesh.nodes.len() as f64;
    let mut nnz = dofs;
    for b in &mesh.blocks {
        let k = 3.0 * b.nodes_per_element() as f64;
        nnz += b.len() as f64 * k * k / 2.0;
    }
    dofs * 8.0 * 12.0 + nnz * 12.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_billion_element_box_is_refused_and_a_small_one_is_not() {
        // 1000^3 H8: 1e9 elements x 8 nodes x 8 bytes alone is 64 GB
        let e = check_memory("box", box_bytes([1000, 1000, 1000], 1, 8));
        if machine_memory().is_some_and(|m| m < 64e9) {
            assert!(e.unwrap_err().to_string().contains("available"));
        }
        let e = check_memory("box", box_bytes([3_000_000_000; 3], 1, 8)).unwrap_err();
        assert!(e.to_string().contains("address"), "{e}");
        check_memory("box", box_bytes([10, 10, 10], 2, 27)).unwrap();
    }
}
