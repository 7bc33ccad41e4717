//! Results on disk: `summary.json` (numbers a script can check) and
//! `results.vtu` (ParaView: displacement as point data, stress and von Mises
//! stress averaged over each cell's integration points as cell data).
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
use junta_core::element::{ElementContext, StepInfo};
use junta_core::state::StateStore;
use junta_core::{Model, PenaltyRole};
use junta_interface::advisor::STIFF_FACTOR;
use junta_interface::{CohesiveVerdict, PenaltyVerdict};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

/// Cell-averaged output of every solid element, in block order, and the
/// range of each stress component over the integration points per block.
pub struct CellResults {
    /// Per solid block: (name, stress_min, stress_max) over all points.
    pub ranges: Vec<(String, [f64; 6], [f64; 6])>,
    /// Average stress per cell (Voigt `[xx, yy, zz, xy, yz, zx]`).
    pub stress: Vec<[f64; 6]>,
    /// Average von Mises stress per cell.
    pub mises: Vec<f64>,
    /// Average second Piola-Kirchhoff stress per cell, when an element
    /// reports it (large deformation: `stress` is then the Cauchy stress).
    pub pk2_stress: Option<Vec<[f64; 6]>>,
}

/// Average integration-point outputs over each solid cell (a linear
/// analysis: the model's whole temperature change, if it has one).
pub fn cell_results(model: &Model, u: &[f64], state: &StateStore) -> Result<CellResults> {
    cell_results_at(model, u, state, StepInfo::default())
}

/// [`cell_results`] for the state of increment `step` (laws whose answer
/// depends on the increment, such as a release schedule, need it).
pub fn cell_results_at(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    step: StepInfo,
) -> Result<CellResults> {
    let mut stress = Vec::with_capacity(model.mesh.num_elements());
    let mut mises = Vec::with_capacity(model.mesh.num_elements());
    let mut pk2 = Vec::with_capacity(model.mesh.num_elements());
    let mut any_pk2 = false;
    let mut ranges = Vec::new();
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_solid() {
            continue;
        }
        let mut lo = [f64::INFINITY; 6];
        let mut hi = [f64::NEG_INFINITY; 6];
        for e in 0..b.len() {
            let pts = element_points(model, u, state, bi, e, step)?;
            for p in &pts {
                if let Some(v) = p.get("stress") {
                    for k in 0..6 {
                        lo[k] = lo[k].min(v[k]);
                        hi[k] = hi[k].max(v[k]);
                    }
                }
            }
            let mut s = [0.0; 6];
            let mut s2 = [0.0; 6];
            let mut m = 0.0;
            let np = pts.len().max(1) as f64;
            for p in &pts {
                if let Some(v) = p.get("stress") {
                    for k in 0..6 {
                        s[k] += v[k] / np;
                    }
                }
                if let Some(v) = p.get("pk2_stress") {
                    any_pk2 = true;
                    for k in 0..6 {
                        s2[k] += v[k] / np;
                    }
                }
                if let Some(v) = p.get("mises") {
                    m += v[0] / np;
                }
            }
            stress.push(s);
            pk2.push(s2);
            mises.push(m);
        }
        ranges.push((b.name.clone(), lo, hi));
    }
    Ok(CellResults {
        ranges,
        stress,
        mises,
        pk2_stress: any_pk2.then_some(pk2),
    })
}

/// Integration-point outputs of element `e` of block `bi`.
pub fn element_points(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    bi: usize,
    e: usize,
    step: StepInfo,
) -> Result<Vec<junta_core::PointOutput>> {
    let b = &model.mesh.blocks[bi];
    let nodes = b.element(e);
    let coords: Vec<[f64; 3]> = nodes.iter().map(|&n| model.mesh.nodes[n]).collect();
    let disp: Vec<f64> = nodes
        .iter()
        .flat_map(|&n| u[3 * n..3 * n + 3].iter().copied())
        .collect();
    // solids see the temperature change of the increment (interfaces none)
    let temperature: Option<Vec<f64>> = model
        .temperature
        .as_ref()
        .filter(|_| b.shape.is_solid())
        .map(|t| {
            nodes
                .iter()
                .map(|&n| step.temperature_factor * t[n])
                .collect()
        });
    let ctx = ElementContext {
        coords: &coords,
        disp: &disp,
        state_committed: &state.committed[state.range(bi, e)],
        step,
        law_responses: None,
        temperature: temperature.as_deref(),
    };
    model.elements[bi]
        .point_outputs(&ctx)
        .with_context(|| format!("output of element {e} of block `{}`", b.name))
}

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
        write_array(&mut w, "block", 1, block_ids)?;
        write_ints(&mut w, "element_id", "Int64", element_ids)?;
        writeln!(w, "      </CellData>")?;
        vtu_tail(&mut w)
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

/// The orderings a direct solver computed, name -> predicted factor
/// non-zeros (`{}` for iterative solvers), for `summary.json`.
pub fn ordering_candidates(report: &junta_core::SolveReport) -> serde_json::Value {
    serde_json::Value::Object(
        report
            .ordering_candidates
            .iter()
            .map(|(k, n)| (k.clone(), serde_json::json!(n)))
            .collect(),
    )
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

/// Integration-point output of one interface block.
pub struct InterfaceResults {
    /// Block index.
    pub block: usize,
    /// Points of every element, element-major (`points_per_element` each).
    pub points: Vec<junta_core::PointOutput>,
    /// Points per element.
    pub points_per_element: usize,
}

/// Point outputs of every interface block.
pub fn interface_results(
    model: &Model,
    u: &[f64],
    state: &StateStore,
) -> Result<Vec<InterfaceResults>> {
    interface_results_at(model, u, state, StepInfo::default())
}

/// [`interface_results`] for the state of increment `step`.
pub fn interface_results_at(
    model: &Model,
    u: &[f64],
    state: &StateStore,
    step: StepInfo,
) -> Result<Vec<InterfaceResults>> {
    let mut out = Vec::new();
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_interface() {
            continue;
        }
        let mut points = Vec::new();
        for e in 0..b.len() {
            points.extend(element_points(model, u, state, bi, e, step)?);
        }
        out.push(InterfaceResults {
            block: bi,
            points_per_element: model.elements[bi].num_points(),
            points,
        });
    }
    Ok(out)
}

fn component_range(points: &[junta_core::PointOutput], name: &str) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        if let Some(v) = p.get(name) {
            for c in 0..3 {
                lo[c] = lo[c].min(v[c]);
                hi[c] = hi[c].max(v[c]);
            }
        }
    }
    (lo, hi)
}

/// Values every interface point carries whatever its law; the other
/// scalar values of a point are its law's outputs
/// ([`junta_core::InterfaceLaw::output_names`]).
pub const FIXED_POINT_VALUES: &[&str] = &[
    "jump",
    "traction",
    "frame",
    "area",
    "state",
    "failed",
    "failure_index",
];

/// Names of the law outputs present in the interface points, in the order
/// first met.
pub fn law_output_names(res: &[InterfaceResults]) -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for r in res {
        if let Some(p) = r.points.first() {
            for (n, v) in &p.values {
                if v.len() == 1 && !FIXED_POINT_VALUES.contains(n) && !names.contains(n) {
                    names.push(n);
                }
            }
        }
    }
    names
}

/// Energies and areas of one interface block, from its law outputs:
/// fracture and viscous energy (integrals of the per-area densities),
/// damaged area (damage >= 0.99) and process-zone area (0 < damage < 0.99).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InterfaceEnergy {
    /// Fracture energy dissipated in the block (integral of the points'
    /// `dissipated_energy` density over their area).
    pub dissipated_energy: f64,
    /// Energy dissipated by viscous regularisation (same integral of
    /// `viscous_energy`).
    pub viscous_energy: f64,
    /// Area of the points with damage >= 0.99.
    pub damaged_area: f64,
    /// Area of the points with 0 < damage < 0.99 (the process zone).
    pub process_zone_area: f64,
    /// Whether the law reports damage (else the numbers are zero).
    pub has_damage: bool,
    /// Energy dissipated by friction or interface plasticity (integral of
    /// the law output `frictional_dissipation`).
    pub frictional_dissipation: f64,
    /// Whether a law reports frictional dissipation.
    pub has_friction: bool,
}

/// [`InterfaceEnergy`] of one block's points.
pub fn interface_energy(r: &InterfaceResults) -> InterfaceEnergy {
    use junta_core::law::output;
    let mut e = InterfaceEnergy::default();
    for p in &r.points {
        // Under nlgeom a point reports its current `area` and its
        // `reference_area`: energies and crack areas are integrated over
        // the reference one (the crack's extent on the undeformed surface;
        // the current mid-surface of a peeled-off point shrinks as its faces
        // move apart, e.g. by 1/sqrt(2) once the faces stand at 90 degrees,
        // while its dissipated energy stays). The law's densities are per
        // current area while a point softens, so the energy is exact where
        // the mid-surface keeps its area while the point softens (openings
        // small against the element).
        let area = p
            .get("reference_area")
            .or_else(|| p.get("area"))
            .map_or(0.0, |a| a[0]);
        if let Some(d) = p.get(output::DISSIPATED_ENERGY) {
            e.dissipated_energy += d[0] * area;
        }
        if let Some(d) = p.get(output::VISCOUS_ENERGY) {
            e.viscous_energy += d[0] * area;
        }
        if let Some(d) = p.get(output::FRICTIONAL_DISSIPATION) {
            e.has_friction = true;
            e.frictional_dissipation += d[0] * area;
        }
        if let Some(d) = p.get(output::DAMAGE) {
            e.has_damage = true;
            if d[0] >= output::DAMAGED_THRESHOLD {
                e.damaged_area += area;
            } else if d[0] > 0.0 {
                e.process_zone_area += area;
            }
        }
    }
    e
}

/// `summary.json` entry `interfaces`: per block, ranges of the local
/// tractions `[t1, t2, tn]` and jumps over all integration points.
pub fn interface_summary(model: &Model, res: &[InterfaceResults]) -> Value {
    let mut m = serde_json::Map::new();
    for r in res {
        let (tmin, tmax) = component_range(&r.points, "traction");
        let (jmin, jmax) = component_range(&r.points, "jump");
        let area: f64 = r
            .points
            .iter()
            .filter_map(|p| p.get("area"))
            .map(|a| a[0])
            .sum();
        let failed = r
            .points
            .iter()
            .filter(|p| p.get("failed").is_some_and(|f| f[0] > 0.5))
            .count();
        let b = &model.mesh.blocks[r.block];
        let energy = interface_energy(r);
        let mut entry = json!({
                "element": b.element_type,
                "elements": b.len(),
                "points": r.points.len(),
                "area": area,
                "traction_min": tmin,
                "traction_max": tmax,
                "jump_min": jmin,
                "jump_max": jmax,
                "failed_points": failed,
                "failed_fraction": failed as f64 / r.points.len().max(1) as f64,
        });
        if energy.has_damage {
            let o = entry.as_object_mut().expect("json object");
            o.insert("dissipated_energy".into(), json!(energy.dissipated_energy));
            o.insert("viscous_energy".into(), json!(energy.viscous_energy));
            o.insert("damaged_area".into(), json!(energy.damaged_area));
            o.insert("process_zone_area".into(), json!(energy.process_zone_area));
        }
        if energy.has_friction {
            let o = entry.as_object_mut().expect("json object");
            o.insert(
                "frictional_dissipation".into(),
                json!(energy.frictional_dissipation),
            );
            // points per contact state (stick / slip / open)
            let mut counts = [0usize; 3];
            for p in &r.points {
                if let Some(s) = p.get(junta_core::law::output::SLIP_STATE) {
                    counts[(s[0].round() as usize).min(2)] += 1;
                }
            }
            o.insert(
                "slip_state_points".into(),
                json!({ "stick": counts[0], "slip": counts[1], "open": counts[2] }),
            );
        }
        m.insert(b.name.clone(), entry);
    }
    Value::Object(m)
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

/// `summary.json` entry `solids`: per solid block, the range of each stress
/// component (Voigt `[xx, yy, zz, xy, yz, zx]`) over its integration points.
pub fn solid_summary(cells: &CellResults) -> Value {
    let mut m = serde_json::Map::new();
    for (name, lo, hi) in &cells.ranges {
        m.insert(name.clone(), json!({ "stress_min": lo, "stress_max": hi }));
    }
    Value::Object(m)
}

/// The penalty advisor of every interface block, as JSON and as text
/// lines, and the lines that are warnings (a verdict other than good).
///
/// A constraint penalty gets the paper's error analysis (eqs. 41-55) and
/// its recommended `d_op`; a cohesive law's penalty gets the compliance it
/// adds to the solids and Turon's bound instead (see
/// [`junta_interface::advisor`]).
pub fn penalty_advice(
    model: &Model,
    thickness: &dyn Fn(&str) -> Option<f64>,
) -> Result<(Value, Vec<String>, Vec<String>)> {
    let mut m = serde_json::Map::new();
    let mut lines = Vec::new();
    let mut warnings = Vec::new();
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_interface() {
            continue;
        }
        let a = junta_interface::penalty_advice(model, bi, thickness(&b.name))?;
        let turon_t = a
            .turon
            .map(|k| format!("; Turon K = 50 E/t = {k:.3e}"))
            .unwrap_or_default();
        let (line, good, entry) = if a.role == PenaltyRole::Cohesive {
            cohesive_penalty_line(&a, &turon_t)
        } else {
            let verdict = match a.verdict {
                PenaltyVerdict::TooLow => {
                    "too low: the constraint error dominates (interpenetration / slip)"
                }
                PenaltyVerdict::Good => "good: within 10x of the error balance",
                PenaltyVerdict::TooHigh => "too high: round-off dominates (the solve loses digits)",
            };
            let line = format!(
                "interface `{}`: k_min = {:.3e}, n = {}, eps_op = k_min/sqrt(n e_c) = {:.3e} (force/length); \
                 area per node pair {:.3e} -> recommended d_op = {:.3e}; scene d3 = {:.3e}: {verdict} \
                 (estimated constraint error {:.1e}, round-off {:.1e}; best attainable {:.1e}){turon_t}",
                a.block,
                a.k_min,
                a.n,
                a.eps_op,
                a.area_per_pair,
                a.d_op,
                a.d_scene[2],
                a.constraint_error,
                a.roundoff_error,
                a.best_error,
            );
            let entry = json!({
                "role": a.role.name(),
                "k_min": a.k_min, "n": a.n, "e_c": a.e_c, "eps_op": a.eps_op,
                "area": a.area, "pairs": a.pairs, "area_per_pair": a.area_per_pair,
                "d_op": a.d_op, "d_scene": a.d_scene,
                "constraint_error": a.constraint_error, "roundoff_error": a.roundoff_error,
                "best_error": a.best_error, "verdict": format!("{:?}", a.verdict), "turon": a.turon,
            });
            (line, a.verdict == PenaltyVerdict::Good, entry)
        };
        if !good {
            warnings.push(line.clone());
        }
        lines.push(line);
        m.insert(a.block.clone(), entry);
    }
    Ok((Value::Object(m), lines, warnings))
}

/// The advisor's line, verdict and JSON for a cohesive law's penalty
/// (never the constraint optimum `d_op` as a recommendation: it appears
/// only as the round-off ceiling).
fn cohesive_penalty_line(
    a: &junta_interface::PenaltyAdvice,
    turon_t: &str,
) -> (String, bool, Value) {
    let Some(c) = a.cohesive else {
        let line = format!(
            "interface `{}`: cohesive law, K = {:.3e}: no solid of finite thickness with a modulus \
             across the interface beside it, so the penalty cannot be judged against the solids' \
             compliance (Turon: K >= 50 E_33 / t with t the thickness of the body beside it){turon_t}",
            a.block, a.d_scene[2]
        );
        let entry = json!({
            "role": a.role.name(), "d_scene": a.d_scene, "verdict": "unknown", "turon": a.turon,
        });
        return (line, true, entry);
    };
    let ceiling = if c.stiff_limit < STIFF_FACTOR * c.turon_bound {
        format!(
            "the round-off balance of the constraint analysis (eq. 55) {:.3e}",
            c.stiff_limit
        )
    } else {
        format!("{STIFF_FACTOR:.0e} x Turon's bound = {:.3e}", c.stiff_limit)
    };
    let verdict = match c.verdict {
        CohesiveVerdict::TooCompliant => format!(
            "too compliant: the penalty adds more than 2% compliance to the solids beside the \
             interface: raise K to at least Turon's bound {:.3e}",
            c.turon_bound
        ),
        CohesiveVerdict::Good => format!(
            "good: K is {:.3} x Turon's bound and below the stiff limit ({ceiling})",
            c.penalty / c.turon_bound,
        ),
        CohesiveVerdict::TooStiff => format!(
            "too stiff: above {ceiling}: a stiffer penalty gains no accuracy but invites traction \
             oscillations ahead of the crack and an ill-conditioned tangent; \
             K = {:.3e} .. {:.3e} (1 to 10 x Turon's bound 50 E_33/t) suffices",
            c.turon_bound,
            10.0 * c.turon_bound
        ),
    };
    let line = format!(
        "interface `{}`: cohesive law (its penalty is part of the model, not a constraint): \
         K = {:.3e}, E_33 = {:.4e}, arm thickness t = {:.4e}: the interface compliance 1/K = {:.3e} \
         is {:.2}% of the arm's t/E_33 = {:.3e}; Turon's bound K >= 50 E_33/t = {:.3e}: {verdict}{turon_t}",
        a.block,
        c.penalty,
        c.modulus_normal,
        c.arm_thickness,
        1.0 / c.penalty,
        100.0 * c.compliance_ratio,
        c.arm_thickness / c.modulus_normal,
        c.turon_bound,
    );
    let entry = json!({
        "role": a.role.name(),
        "d_scene": a.d_scene,
        "modulus_normal": c.modulus_normal,
        "arm_thickness": c.arm_thickness,
        "compliance_ratio": c.compliance_ratio,
        "turon_bound": c.turon_bound,
        "stiff_limit": c.stiff_limit,
        "roundoff_limit": a.d_op,
        "k_min": a.k_min, "n": a.n, "area_per_pair": a.area_per_pair,
        "verdict": c.verdict.name(),
        "turon": a.turon,
    });
    (line, c.verdict == CohesiveVerdict::Good, entry)
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

/// Mesh advice of every softening interface (cohesive-zone length,
/// elements spanning it, verdict, Turon's strengths) as JSON and text
/// lines, and the laws' parameter warnings as text lines.
pub fn cohesive_zone_advice(model: &Model) -> Result<(Value, Vec<String>, Vec<String>)> {
    let mut m = serde_json::Map::new();
    let mut lines = Vec::new();
    let mut warnings = Vec::new();
    for (bi, b) in model.mesh.blocks.iter().enumerate() {
        if !b.shape.is_interface() {
            continue;
        }
        for w in model.elements[bi].warnings() {
            warnings.push(format!("interface `{}`: {w}", b.name));
        }
        let Some(a) = junta_interface::cohesive_zone_advice(model, bi)? else {
            continue;
        };
        lines.push(a.message());
        let mode = |z: &junta_interface::cohesive_zone::ZoneLengths| {
            json!({
                "strength": z.strength, "toughness": z.toughness,
                "hillerborg": z.hillerborg, "rice": z.rice, "hui": z.hui,
                "slender": z.slender, "length": z.length,
                "turon_reduced_strength": z.reduced_strength,
            })
        };
        m.insert(
            a.block.clone(),
            json!({
                "modulus_normal": a.modulus_normal,
                "modulus_along": a.modulus_along,
                "arm_thickness": a.arm_thickness,
                "element_length_min": a.element_length_min,
                "element_length_max": a.element_length_max,
                "mode_i": mode(&a.mode_i),
                "mode_ii": mode(&a.mode_ii),
                "cohesive_zone_length": a.length,
                "crack_region": a.crack_region.as_ref().map(|r| json!({
                    "front_edges": r.front_edges, "radius": r.radius, "elements": r.elements,
                    "element_length_min": r.element_length_min,
                    "element_length_max": r.element_length_max,
                })),
                "elements_in_zone": a.elements_in_zone,
                "verdict": a.verdict.name(),
                "law_warnings": model.elements[bi].warnings(),
            }),
        );
    }
    Ok((Value::Object(m), lines, warnings))
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

/// `summary.json` `distributed` of a run over MPI ranks (`null` in one
/// process): the ranks, and per rank its elements, the nodes they touch
/// and of those the nodes shared with other ranks (the partition's cut,
/// [`junta_core::distributed::partition_cut`]), with the bytes per Newton
/// iteration each rank exchanges.
pub fn distributed_summary(model: &junta_core::Model) -> serde_json::Value {
    use junta_core::distributed::{collective, partition_cut, partition_elements};
    let Some(c) = collective() else {
        return serde_json::Value::Null;
    };
    let ranks = c.size();
    let cut = partition_cut(&model.mesh, &partition_elements(&model.mesh, ranks), ranks);
    let n = model.dofs.num_free as f64;
    let states: usize = model
        .mesh
        .blocks
        .iter()
        .zip(&model.elements)
        .map(|(b, e)| b.len() * e.state_len())
        .sum();
    serde_json::json!({
        "ranks": ranks,
        "partition": "recursive coordinate bisection of the element centroids, weighted by element matrix size",
        "elements": cut.elements,
        "nodes": cut.nodes,
        "shared_nodes": cut.shared_nodes,
        // PETSc's matrix and vector halo: 3 dofs of each shared node, both ways
        "halo_bytes_per_iteration": cut.shared_nodes.iter().map(|s| 2 * 3 * 8 * s).collect::<Vec<_>>(),
        // replicated vectors: the force sum, the state copy and the solution
        // gathered on every rank, each the whole length
        "replicated_bytes_per_iteration": 8.0 * (2.0 * 3.0 * model.mesh.nodes.len() as f64 + states as f64 + n),
    })
}
