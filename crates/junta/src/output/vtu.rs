//! The VTU/PVD writers: `results.vtu` (ParaView: displacement as point
//! data, stress and von Mises stress averaged over each cell's integration
//! points as cell data), the interfaces' files and the `.pvd` collections.
//!
//! Our hexahedron node orders are VTK's (see `junta_core::topology`), so
//! cells are written without permutation as VTK_HEXAHEDRON (12),
//! VTK_QUADRATIC_HEXAHEDRON (25) and VTK_TRIQUADRATIC_HEXAHEDRON (29);
//! wedges as VTK_WEDGE (13) / VTK_QUADRATIC_WEDGE (26) through
//! `WEDGE15_TO_VTK`.
//!
//! Interfaces go to `interfaces.vtu` as their mid-surface: one point per
//! (bottom, top) node pair, at the pair's mid-point, carrying the jump, and
//! one cell per element of its side's shape and node order
//! (`CellShape::vtk_type`): INTER8 / INTER16 / INTER18 as VTK_QUAD (9) /
//! VTK_QUADRATIC_QUAD (23) / VTK_BIQUADRATIC_QUAD (28), INTER6 / INTER12 as
//! VTK_TRIANGLE (5) / VTK_QUADRATIC_TRIANGLE (22; corners then mid-edges
//! 0-1, 1-2, 2-0, our order). A zero-thickness VTK_WEDGE would have two
//! coincident triangles and no volume; the mid-surface triangle is the
//! analogue of the quadrilaterals written for INTER8..18.

use crate::error::{Context, Result};
use crate::post::fields::{cell_results_at, law_output_names, CellResults, InterfaceResults};
use junta_core::element::StepInfo;
use junta_core::state::StateStore;
use junta_core::Model;
use std::io::Write;
use std::path::Path;

/// Files with more points than this write their arrays in binary
/// (VTK XML appended raw data: per array a UInt64 byte count and the
/// little-endian values), smaller ones in ascii (readable as text).
pub const VTU_BINARY_POINTS: usize = 50_000;

/// A VTU file being written: the XML goes to `w`; in binary mode the
/// arrays' bytes collect in `appended` and [`vtu_tail`] writes them after
/// the XML (`<AppendedData encoding="raw">`).
struct Vtu<W: Write> {
    w: W,
    binary: bool,
    appended: Vec<u8>,
}

impl<W: Write> Vtu<W> {
    /// Binary when the file has more than [`VTU_BINARY_POINTS`] points.
    fn new(w: W, points: usize) -> Self {
        Self::with_format(w, points > VTU_BINARY_POINTS)
    }
    fn with_format(w: W, binary: bool) -> Self {
        Vtu {
            w,
            binary,
            appended: Vec::new(),
        }
    }
    /// Open a binary array (`<DataArray ... format="appended" offset=.../>`)
    /// and queue its bytes.
    fn appended_array(&mut self, attrs: &str, bytes: &[u8]) -> std::io::Result<()> {
        writeln!(
            self.w,
            "        <DataArray {attrs} format=\"appended\" offset=\"{}\"/>",
            self.appended.len()
        )?;
        self.appended
            .extend_from_slice(&(bytes.len() as u64).to_le_bytes());
        self.appended.extend_from_slice(bytes);
        Ok(())
    }
}

impl<W: Write> Write for Vtu<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.w.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.w.flush()
    }
}

fn write_array<W: Write>(
    w: &mut Vtu<W>,
    name: &str,
    comps: usize,
    data: impl Iterator<Item = f64>,
) -> std::io::Result<()> {
    let attrs = format!("type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{comps}\"");
    if w.binary {
        let bytes: Vec<u8> = data.flat_map(f64::to_le_bytes).collect();
        return w.appended_array(&attrs, &bytes);
    }
    writeln!(w, "        <DataArray {attrs} format=\"ascii\">")?;
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

/// Write `results.vtu` (solid blocks; interfaces go to `interfaces.vtu`).
pub fn write_vtu(path: &Path, model: &Model, u: &[f64], cells: &CellResults) -> Result<()> {
    let f =
        std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let mut w = Vtu::new(std::io::BufWriter::new(f), model.mesh.nodes.len());
    let mesh = &model.mesh;
    let solids: Vec<&junta_core::mesh::ElementBlock> =
        mesh.blocks.iter().filter(|b| b.shape.is_solid()).collect();
    let ncells: usize = solids.iter().map(|b| b.len()).sum();
    // wedges: VTK's node order differs from ours (Abaqus'), see WEDGE15_TO_VTK
    let conn = solids.iter().flat_map(|b| {
        let npe = b.nodes_per_element();
        let wedge = matches!(
            b.shape,
            junta_core::topology::CellShape::Wedge6 | junta_core::topology::CellShape::Wedge15
        );
        b.connectivity.iter().enumerate().map(move |(i, &n)| {
            if wedge {
                let (e, k) = (i / npe, i % npe);
                b.connectivity[e * npe + junta_core::topology::WEDGE15_TO_VTK[k]] as u64
            } else {
                n as u64
            }
        })
    });
    let offsets = solids
        .iter()
        .flat_map(|b| std::iter::repeat_n(b.nodes_per_element(), b.len()))
        .scan(0u64, |acc, n| {
            *acc += n as u64;
            Some(*acc)
        });
    let types = solids
        .iter()
        .flat_map(|b| std::iter::repeat_n(b.shape.vtk_type() as u64, b.len()));
    let block_ids = mesh
        .blocks
        .iter()
        .enumerate()
        .filter(|(_, b)| b.shape.is_solid())
        .flat_map(|(i, b)| std::iter::repeat_n(i as f64, b.len()));
    let element_ids = mesh
        .blocks
        .iter()
        .enumerate()
        .filter(|(_, b)| b.shape.is_solid())
        .flat_map(|(i, b)| (0..b.len()).map(move |e| mesh.element_label(i, e) as u64));
    (|| -> std::io::Result<()> {
        vtu_head(&mut w, mesh.nodes.len(), ncells)?;
        write_array(
            &mut w,
            "Points",
            3,
            mesh.nodes.iter().flat_map(|p| p.iter().copied()),
        )?;
        writeln!(w, "      </Points>\n      <Cells>")?;
        write_ints(&mut w, "connectivity", "Int64", conn)?;
        write_ints(&mut w, "offsets", "Int64", offsets)?;
        write_ints(&mut w, "types", "UInt8", types)?;
        writeln!(
            w,
            "      </Cells>\n      <PointData Vectors=\"displacement\">"
        )?;
        write_array(&mut w, "displacement", 3, u.iter().copied())?;
        // the input's own numbers (deck or mesh-file labels)
        write_ints(
            &mut w,
            "node_id",
            "Int64",
            (0..mesh.nodes.len()).map(|n| mesh.node_label(n) as u64),
        )?;
        writeln!(w, "      </PointData>\n      <CellData Tensors=\"stress\">")?;
        write_array(
            &mut w,
            "stress",
            6,
            cells.stress.iter().flat_map(|s| s.iter().copied()),
        )?;
        write_array(&mut w, "mises", 1, cells.mises.iter().copied())?;
        if let Some(pk2) = &cells.pk2_stress {
            write_array(
                &mut w,
                "pk2_stress",
                6,
                pk2.iter().flat_map(|s| s.iter().copied()),
            )?;
        }
        for (name, v) in &cells.extra {
            write_array(&mut w, name, 1, v.iter().copied())?;
        }
        if let Some(sl) = &cells.material_stress {
            write_array(
                &mut w,
                "material_stress",
                6,
                sl.iter().flat_map(|s| s.iter().copied()),
            )?;
        }
        write_array(&mut w, "block", 1, block_ids)?;
        write_ints(&mut w, "element_id", "Int64", element_ids)?;
        writeln!(w, "      </CellData>")?;
        vtu_tail(&mut w)
    })()
    .with_context(|| format!("cannot write {}", path.display()))
}

/// Write `interfaces.vtu` (every interface element as a quadrilateral on
/// its mid-surface, cell data: mean local traction and jump; point data:
/// the global displacement jump `u_top - u_bottom` of each node pair) and
/// `interface_points.vtu` (one vertex per integration point with its local
/// traction, jump, normal and law state), so that ParaView shows the
/// interfaces as they are computed.
pub fn write_interface_vtu(
    dir: &Path,
    model: &Model,
    u: &[f64],
    res: &[InterfaceResults],
) -> Result<()> {
    write_interface_vtu_named(dir, "", model, u, res)
}

/// [`write_interface_vtu`] with a suffix on the file names (`interfaces<suffix>.vtu`).
///
/// Stages: `MidSurface::of` gathers the mid-surface cells,
/// `write_mid_surface_vtu` writes them, `write_interface_points_vtu`
/// writes the integration points.
pub fn write_interface_vtu_named(
    dir: &Path,
    suffix: &str,
    model: &Model,
    u: &[f64],
    res: &[InterfaceResults],
) -> Result<()> {
    if res.is_empty() {
        return Ok(());
    }
    let law_names = law_output_names(res);
    let surface = MidSurface::of(model, u, res, &law_names);
    write_mid_surface_vtu(
        &dir.join(format!("interfaces{suffix}.vtu")),
        &surface,
        &law_names,
    )?;
    write_interface_points_vtu(
        &dir.join(format!("interface_points{suffix}.vtu")),
        res,
        &law_names,
    )
}

/// The interfaces as their mid-surface (module docs): one point per
/// (bottom, top) node pair at `(x_bot + x_top) / 2` with the jump
/// `u_top - u_bot`, one cell per element with the means over its
/// integration points of the local traction, the local jump and each
/// scalar law output.
struct MidSurface {
    points: Vec<[f64; 3]>,
    jumps: Vec<[f64; 3]>,
    conn: Vec<usize>,
    offsets: Vec<usize>,
    types: Vec<u8>,
    cell_t: Vec<[f64; 3]>,
    cell_j: Vec<[f64; 3]>,
    cell_block: Vec<f64>,
    /// Per name of `law_names`, the cell means.
    cell_law: Vec<Vec<f64>>,
}

impl MidSurface {
    fn of(model: &Model, u: &[f64], res: &[InterfaceResults], law_names: &[&str]) -> Self {
        let mesh = &model.mesh;
        let mut s = MidSurface {
            points: Vec::new(),
            jumps: Vec::new(),
            conn: Vec::new(),
            offsets: Vec::new(),
            types: Vec::new(),
            cell_t: Vec::new(),
            cell_j: Vec::new(),
            cell_block: Vec::new(),
            cell_law: vec![Vec::new(); law_names.len()],
        };
        let mut index = std::collections::HashMap::new();
        for r in res {
            let b = &mesh.blocks[r.block];
            let m = b.nodes_per_element() / 2;
            for e in 0..b.len() {
                let nodes = b.element(e);
                for a in 0..m {
                    let (bot, top) = (nodes[a], nodes[m + a]);
                    let id = *index.entry((bot, top)).or_insert_with(|| {
                        let p = mesh.nodes[bot];
                        let q = mesh.nodes[top];
                        s.points.push([
                            0.5 * (p[0] + q[0]),
                            0.5 * (p[1] + q[1]),
                            0.5 * (p[2] + q[2]),
                        ]);
                        s.jumps
                            .push([0, 1, 2].map(|c| u[3 * top + c] - u[3 * bot + c]));
                        s.points.len() - 1
                    });
                    s.conn.push(id);
                }
                s.offsets.push(s.conn.len());
                s.types.push(b.shape.vtk_type());
                let pts = &r.points[e * r.points_per_element..(e + 1) * r.points_per_element];
                s.push_means(pts, law_names, r.block);
            }
        }
        s
    }

    /// The cell data of one element from its integration points `pts`.
    fn push_means(&mut self, pts: &[junta_core::PointOutput], law_names: &[&str], block: usize) {
        let mean = |name: &str| {
            let mut s = [0.0; 3];
            for p in pts {
                if let Some(v) = p.get(name) {
                    for c in 0..3 {
                        s[c] += v[c] / pts.len() as f64;
                    }
                }
            }
            s
        };
        for (k, name) in law_names.iter().enumerate() {
            let v: f64 = pts
                .iter()
                .map(|p| p.get(name).map_or(0.0, |v| v[0]))
                .sum::<f64>()
                / pts.len().max(1) as f64;
            self.cell_law[k].push(v);
        }
        self.cell_t.push(mean("traction"));
        self.cell_j.push(mean("jump"));
        self.cell_block.push(block as f64);
    }
}

/// Write the mid-surface cells to `interfaces<suffix>.vtu` (`path`): point
/// data `jump_global`; cell data `traction_local`, `jump_local`, `block`
/// and the scalar law outputs.
fn write_mid_surface_vtu(path: &Path, s: &MidSurface, law_names: &[&str]) -> Result<()> {
    let f =
        std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let mut w = Vtu::new(std::io::BufWriter::new(f), s.points.len());
    (|| -> std::io::Result<()> {
        vtu_head(&mut w, s.points.len(), s.types.len())?;
        write_array(
            &mut w,
            "Points",
            3,
            s.points.iter().flat_map(|p| p.iter().copied()),
        )?;
        writeln!(w, "      </Points>\n      <Cells>")?;
        write_ints(
            &mut w,
            "connectivity",
            "Int64",
            s.conn.iter().map(|&v| v as u64),
        )?;
        write_ints(
            &mut w,
            "offsets",
            "Int64",
            s.offsets.iter().map(|&v| v as u64),
        )?;
        write_ints(&mut w, "types", "UInt8", s.types.iter().map(|&v| v as u64))?;
        writeln!(
            w,
            "      </Cells>\n      <PointData Vectors=\"jump_global\">"
        )?;
        write_array(
            &mut w,
            "jump_global",
            3,
            s.jumps.iter().flat_map(|p| p.iter().copied()),
        )?;
        writeln!(w, "      </PointData>\n      <CellData>")?;
        write_array(
            &mut w,
            "traction_local",
            3,
            s.cell_t.iter().flat_map(|p| p.iter().copied()),
        )?;
        write_array(
            &mut w,
            "jump_local",
            3,
            s.cell_j.iter().flat_map(|p| p.iter().copied()),
        )?;
        write_array(&mut w, "block", 1, s.cell_block.iter().copied())?;
        for (name, values) in law_names.iter().zip(&s.cell_law) {
            write_array(&mut w, name, 1, values.iter().copied())?;
        }
        writeln!(w, "      </CellData>")?;
        vtu_tail(&mut w)
    })()
    .with_context(|| format!("cannot write {}", path.display()))
}

/// Write the integration points of the interfaces to
/// `interface_points<suffix>.vtu` (`path`): one vertex each, with its local
/// traction and jump, normal, failure flag and index, scalar law outputs,
/// plastic jump (when the law has one) and law state.
fn write_interface_points_vtu(
    path: &Path,
    res: &[InterfaceResults],
    law_names: &[&str],
) -> Result<()> {
    let all: Vec<&junta_core::PointOutput> = res.iter().flat_map(|r| r.points.iter()).collect();
    let f =
        std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let mut w = Vtu::new(std::io::BufWriter::new(f), all.len());
    let get3 = |p: &junta_core::PointOutput, name: &str, from: usize| -> [f64; 3] {
        p.get(name)
            .map_or([0.0; 3], |v| [v[from], v[from + 1], v[from + 2]])
    };
    let state_len = all
        .iter()
        .filter_map(|p| p.get("state"))
        .map(|s| s.len())
        .max()
        .unwrap_or(0);
    (|| -> std::io::Result<()> {
        vtu_head(&mut w, all.len(), all.len())?;
        write_array(&mut w, "Points", 3, all.iter().flat_map(|p| p.position))?;
        writeln!(w, "      </Points>\n      <Cells>")?;
        write_ints(&mut w, "connectivity", "Int64", 0..all.len() as u64)?;
        write_ints(&mut w, "offsets", "Int64", 1..=all.len() as u64)?;
        write_ints(&mut w, "types", "UInt8", all.iter().map(|_| 1))?;
        writeln!(w, "      </Cells>\n      <PointData>")?;
        write_array(
            &mut w,
            "traction_local",
            3,
            all.iter().flat_map(|p| get3(p, "traction", 0)),
        )?;
        write_array(
            &mut w,
            "jump_local",
            3,
            all.iter().flat_map(|p| get3(p, "jump", 0)),
        )?;
        write_array(
            &mut w,
            "normal",
            3,
            all.iter().flat_map(|p| get3(p, "frame", 6)),
        )?;
        let scalar = |p: &junta_core::PointOutput, name: &str| p.get(name).map_or(0.0, |v| v[0]);
        write_array(&mut w, "failed", 1, all.iter().map(|p| scalar(p, "failed")))?;
        write_array(
            &mut w,
            "failure_index",
            1,
            all.iter().map(|p| scalar(p, "failure_index")),
        )?;
        for name in law_names {
            write_array(&mut w, name, 1, all.iter().map(|p| scalar(p, name)))?;
        }
        {
            // plastic jump as one vector of the local frame [s1, s2, n]
            use junta_core::law::output as lo;
            if law_names.contains(&lo::PLASTIC_SLIP_1) {
                write_array(
                    &mut w,
                    "plastic_jump_local",
                    3,
                    all.iter().flat_map(|p| {
                        [
                            scalar(p, lo::PLASTIC_SLIP_1),
                            scalar(p, lo::PLASTIC_SLIP_2),
                            scalar(p, lo::PLASTIC_OPENING),
                        ]
                    }),
                )?;
            }
        }
        if state_len > 0 {
            write_array(
                &mut w,
                "state",
                state_len,
                all.iter().flat_map(|p| {
                    (0..state_len).map(move |k| {
                        p.get("state")
                            .and_then(|s| s.get(k))
                            .copied()
                            .unwrap_or(0.0)
                    })
                }),
            )?;
        }
        writeln!(w, "      </PointData>")?;
        vtu_tail(&mut w)
    })()
    .with_context(|| format!("cannot write {}", path.display()))
}

fn vtu_head<W: Write>(w: &mut Vtu<W>, points: usize, cells: usize) -> std::io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(w, "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">")?;
    writeln!(w, "  <UnstructuredGrid>")?;
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{points}\" NumberOfCells=\"{cells}\">"
    )?;
    writeln!(w, "      <Points>")
}

fn vtu_tail<W: Write>(w: &mut Vtu<W>) -> std::io::Result<()> {
    writeln!(w, "    </Piece>\n  </UnstructuredGrid>")?;
    if w.binary {
        write!(w.w, "  <AppendedData encoding=\"raw\">\n   _")?;
        w.w.write_all(&w.appended)?;
        writeln!(w.w, "\n  </AppendedData>")?;
    }
    writeln!(w, "</VTKFile>")?;
    w.flush()
}

fn write_ints<W: Write>(
    w: &mut Vtu<W>,
    name: &str,
    ty: &str,
    data: impl Iterator<Item = u64>,
) -> std::io::Result<()> {
    if w.binary {
        let bytes: Vec<u8> = match ty {
            "UInt8" => data.map(|v| v as u8).collect(),
            "Int64" => data.flat_map(|v| (v as i64).to_le_bytes()).collect(),
            _ => data.flat_map(u64::to_le_bytes).collect(),
        };
        return w.appended_array(&format!("type=\"{ty}\" Name=\"{name}\""), &bytes);
    }
    writeln!(
        w,
        "        <DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">"
    )?;
    for (i, v) in data.enumerate() {
        write!(w, "{v} ")?;
        if i % 20 == 19 {
            writeln!(w)?;
        }
    }
    writeln!(w, "\n        </DataArray>")
}

/// The linear solution scaled to each fraction of the load:
/// `results_<f>.vtu` (and `interfaces_<f>.vtu`) plus `results.pvd`, so that
/// ParaView plays the load steps (valid for linear analyses only).
pub fn write_fractions(
    dir: &Path,
    model: &Model,
    u: &[f64],
    state: &StateStore,
    fractions: &[f64],
) -> Result<()> {
    let mut frames = Vec::new();
    for &f in fractions {
        let uf: Vec<f64> = u.iter().map(|v| v * f).collect();
        // the temperature change scales with the loads (superposition)
        let step = StepInfo {
            temperature_factor: f,
            ..StepInfo::default()
        };
        let cells = cell_results_at(model, &uf, state, step)?;
        let name = format!("results_{:03}.vtu", (f * 100.0).round() as i64);
        write_vtu(&dir.join(&name), model, &uf, &cells)?;
        frames.push((f, name));
    }
    write_pvd(&dir.join("results.pvd"), &frames)
}

/// A ParaView collection file listing `(time, file)` frames.
pub fn write_pvd(path: &Path, frames: &[(f64, String)]) -> Result<()> {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n",
    );
    for (t, f) in frames {
        s += &format!("    <DataSet timestep=\"{t}\" part=\"0\" file=\"{f}\"/>\n");
    }
    s += "  </Collection>\n</VTKFile>\n";
    std::fs::write(path, s).with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The arrays of a small file written both ways: the binary file's
    /// appended block (byte count, then little-endian values at each
    /// array's offset) decodes to exactly the ascii file's values.
    #[test]
    fn binary_vtu_arrays_decode_to_the_ascii_values() {
        let floats: Vec<f64> = (0..12).map(|i| (i as f64) * 0.1 - 1.0 / 3.0).collect();
        let ints: Vec<u64> = vec![7, 0, 123456789012, 3];
        let types: Vec<u64> = vec![12, 25, 13];
        let write = |binary: bool| -> Vec<u8> {
            let mut w = Vtu::with_format(Vec::new(), binary);
            vtu_head(&mut w, 4, 1).unwrap();
            write_array(&mut w, "f", 3, floats.iter().copied()).unwrap();
            write_ints(&mut w, "i", "Int64", ints.iter().copied()).unwrap();
            write_ints(&mut w, "t", "UInt8", types.iter().copied()).unwrap();
            vtu_tail(&mut w).unwrap();
            w.w
        };
        let ascii = String::from_utf8(write(false)).unwrap();
        assert!(!ascii.contains("appended"));
        // ascii values
        let body = |name: &str| -> Vec<String> {
            let at = ascii.find(&format!("Name=\"{name}\"")).unwrap();
            let b = &ascii[at..];
            b[b.find('>').unwrap() + 1..b.find("</DataArray>").unwrap()]
                .split_whitespace()
                .map(str::to_string)
                .collect()
        };
        // binary: the raw bytes after `_`
        let bytes = write(true);
        let text = String::from_utf8_lossy(&bytes).into_owned();
        assert!(text.contains("<AppendedData encoding=\"raw\">"));
        let marker: &[u8] = b"<AppendedData encoding=\"raw\">\n   _";
        let start = bytes
            .windows(marker.len())
            .position(|p| p == marker)
            .unwrap()
            + marker.len();
        let data = &bytes[start..];
        let offset = |name: &str| -> usize {
            let at = text.find(&format!("Name=\"{name}\"")).unwrap();
            let b = &text[at..];
            let o = &b[b.find("offset=\"").unwrap() + 8..];
            o[..o.find('"').unwrap()].parse().unwrap()
        };
        let block = |name: &str| -> &[u8] {
            let o = offset(name);
            let n = u64::from_le_bytes(data[o..o + 8].try_into().unwrap()) as usize;
            &data[o + 8..o + 8 + n]
        };
        let f: Vec<f64> = block("f")
            .chunks(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(f, floats);
        // ascii keeps 10 significant digits
        for (a, b) in body("f").iter().zip(&f) {
            assert!((a.parse::<f64>().unwrap() - b).abs() < 1e-9);
        }
        let i: Vec<u64> = block("i")
            .chunks(8)
            .map(|c| i64::from_le_bytes(c.try_into().unwrap()) as u64)
            .collect();
        assert_eq!(i, ints);
        assert_eq!(
            body("i"),
            ints.iter().map(|v| v.to_string()).collect::<Vec<_>>()
        );
        assert_eq!(block("t"), &[12u8, 25, 13]);
    }
}
