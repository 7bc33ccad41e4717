//! Results on disk: `summary.json` (numbers a script can check) and
//! `results.vtu` (ParaView: displacement as point data, stress and von Mises
//! stress averaged over each cell's integration points as cell data).
//!
//! Our hexahedron node orders are VTK's (see `junta_core::topology`), so
//! cells are written without permutation as VTK_HEXAHEDRON (12),
//! VTK_QUADRATIC_HEXAHEDRON (25) and VTK_TRIQUADRATIC_HEXAHEDRON (29).

use anyhow::{Context, Result};
use junta_core::element::{ElementContext, StepInfo};
use junta_core::state::StateStore;
use junta_core::Model;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

/// Cell-averaged output of every element, in block order.
pub struct CellResults {
    /// Average stress per cell (Voigt `[xx, yy, zz, xy, yz, zx]`).
    pub stress: Vec<[f64; 6]>,
    /// Average von Mises stress per cell.
    pub mises: Vec<f64>,
}

/// Average integration-point outputs over each cell.
pub fn cell_results(model: &Model, u: &[f64], state: &StateStore) -> Result<CellResults> {
    let mut stress = Vec::with_capacity(model.mesh.num_elements());
    let mut mises = Vec::with_capacity(model.mesh.num_elements());
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        let n = b.nodes_per_element();
        let mut coords = vec![[0.0; 3]; n];
        let mut disp = vec![0.0; 3 * n];
        for e in 0..b.len() {
            for (a, &node) in b.element(e).iter().enumerate() {
                coords[a] = model.mesh.nodes[node];
                disp[3 * a..3 * a + 3].copy_from_slice(&u[3 * node..3 * node + 3]);
            }
            let ctx = ElementContext {
                coords: &coords,
                disp: &disp,
                state_committed: &state.committed[state.range(bi, e)],
                step: StepInfo::default(),
            };
            let pts = model.elements[bi]
                .point_outputs(&ctx)
                .with_context(|| format!("output of element {e} of block `{}`", b.name))?;
            let mut s = [0.0; 6];
            let mut m = 0.0;
            let np = pts.len().max(1) as f64;
            for p in &pts {
                if let Some(v) = p.get("stress") {
                    for k in 0..6 {
                        s[k] += v[k] / np;
                    }
                }
                if let Some(v) = p.get("mises") {
                    m += v[0] / np;
                }
            }
            stress.push(s);
            mises.push(m);
        }
    }
    Ok(CellResults { stress, mises })
}

fn write_array<W: Write>(
    w: &mut W,
    name: &str,
    comps: usize,
    data: impl Iterator<Item = f64>,
) -> std::io::Result<()> {
    writeln!(
        w,
        "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"ascii\">"
    )?;
    let mut line = 0;
    for v in data {
        write!(w, "{v:.9e} ")?;
        line += 1;
        if line % comps.max(3) == 0 {
            writeln!(w)?;
        }
    }
    writeln!(w, "\n        </DataArray>")
}

/// Write `results.vtu`.
pub fn write_vtu(path: &Path, model: &Model, u: &[f64], cells: &CellResults) -> Result<()> {
    let f =
        std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let mut w = std::io::BufWriter::new(f);
    let mesh = &model.mesh;
    let ncells = mesh.num_elements();
    (|| -> std::io::Result<()> {
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(w, "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">")?;
        writeln!(w, "  <UnstructuredGrid>")?;
        writeln!(w, "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{ncells}\">", mesh.nodes.len())?;
        writeln!(w, "      <Points>")?;
        write_array(&mut w, "Points", 3, mesh.nodes.iter().flat_map(|p| p.iter().copied()))?;
        writeln!(w, "      </Points>")?;
        writeln!(w, "      <Cells>")?;
        writeln!(w, "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">")?;
        for b in &mesh.blocks {
            for e in 0..b.len() {
                for n in b.element(e) {
                    write!(w, "{n} ")?;
                }
                writeln!(w)?;
            }
        }
        writeln!(w, "        </DataArray>")?;
        writeln!(w, "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">")?;
        let mut off = 0;
        for b in &mesh.blocks {
            for _ in 0..b.len() {
                off += b.nodes_per_element();
                write!(w, "{off} ")?;
            }
        }
        writeln!(w, "\n        </DataArray>")?;
        writeln!(w, "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">")?;
        for b in &mesh.blocks {
            for _ in 0..b.len() {
                write!(w, "{} ", b.shape.vtk_type())?;
            }
        }
        writeln!(w, "\n        </DataArray>")?;
        writeln!(w, "      </Cells>")?;
        writeln!(w, "      <PointData Vectors=\"displacement\">")?;
        write_array(&mut w, "displacement", 3, u.iter().copied())?;
        writeln!(w, "      </PointData>")?;
        writeln!(w, "      <CellData Tensors=\"stress\">")?;
        write_array(&mut w, "stress", 6, cells.stress.iter().flat_map(|s| s.iter().copied()))?;
        write_array(&mut w, "mises", 1, cells.mises.iter().copied())?;
        let blocks = mesh
            .blocks
            .iter()
            .enumerate()
            .flat_map(|(i, b)| std::iter::repeat(i as f64).take(b.len()));
        write_array(&mut w, "block", 1, blocks)?;
        writeln!(w, "      </CellData>")?;
        writeln!(w, "    </Piece>")?;
        writeln!(w, "  </UnstructuredGrid>")?;
        writeln!(w, "</VTKFile>")?;
        w.flush()
    })()
    .with_context(|| format!("cannot write {}", path.display()))
}

/// Elements counted per element type key.
pub fn element_counts(model: &Model) -> BTreeMap<String, usize> {
    let mut m = BTreeMap::new();
    for b in &model.mesh.blocks {
        *m.entry(b.element_type.clone()).or_insert(0) += b.len();
    }
    m
}

/// Largest nodal displacement magnitude.
pub fn displacement_max(u: &[f64]) -> f64 {
    u.chunks(3)
        .map(|c| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt())
        .fold(0.0, f64::max)
}

/// Write a JSON value to a file, pretty.
pub fn write_json(path: &Path, v: &Value) -> Result<()> {
    let s = serde_json::to_string_pretty(v)?;
    std::fs::write(path, s + "\n").with_context(|| format!("cannot write {}", path.display()))
}

/// Reactions on every set that carries a boundary condition.
pub fn reactions(model: &Model, residual: &[f64]) -> Result<Value> {
    let mut m = serde_json::Map::new();
    for s in &model.reaction_sets {
        m.insert(s.clone(), json!(model.set_total(s, residual)?));
    }
    Ok(Value::Object(m))
}

/// Mean displacement of each probe node set.
pub fn probes(model: &Model, sets: &[String], u: &[f64]) -> Result<Value> {
    let mut m = serde_json::Map::new();
    for s in sets {
        let nodes = model.mesh.node_set(s)?;
        let mut mean = [0.0; 3];
        for &n in nodes {
            for c in 0..3 {
                mean[c] += u[3 * n + c] / nodes.len() as f64;
            }
        }
        m.insert(s.clone(), json!(mean));
    }
    Ok(Value::Object(m))
}
