//! Reader for Gmsh MSH 4.1 ASCII files (`$MeshFormat 4.1 0 8`).
//!
//! What is read:
//!
//! - `$PhysicalNames`, `$Entities` (to map entity tags to physical groups),
//!   `$Nodes` (entity blocks, arbitrary tags kept in [`Mesh::node_labels`]),
//!   `$Elements`; any other section is skipped.
//! - Volume elements: 5 (hex8), 17 (hex20), 12 (hex27), 6 (prism6), 18
//!   (prism15). They become one [`ElementBlock`] per physical volume and
//!   shape: block name = physical name (or `volume<tag>` for an entity
//!   outside any physical group), `element_type` = `h8` / `h20` / `h27` /
//!   `wedge6` / `wedge15`, `material` = the physical name.
//!   Each physical volume is also an element set.
//! - Surface elements: 3 (quad4), 16 (quad8), 10 (quad9), 2 (tri3), 9
//!   (tri6). A physical surface becomes a node set (all nodes of its
//!   elements) and a face set: each quadrangle or triangle is matched, by
//!   its corner nodes, to the face of a volume element ([`FaceRef`]; a
//!   triangle to the end face of a wedge). On an internal surface shared
//!   by two volume elements the face whose outward normal agrees with the
//!   surface element's right-hand normal is taken (so orient internal surfaces as you want the pressure to act).
//! - Points (15) and lines (1, 8, 26) only feed node sets of 0D / 1D
//!   physical groups.
//! - A 2D mesh (surface elements and no volume element): the model is a
//!   plane one in the x-y plane (every node at z = 0). Each physical
//!   surface's quadrangles and triangles become a block of plane cells
//!   (`PlaneQuad4/8/9`, `PlaneTri3/6`) with the plane-strain element type
//!   `cpe4` / `cpe8` / `cpe9` / `cpe3` / `cpe6` (a `[[blocks]]` entry picks
//!   another: `cps8`, `cax8`, `cpe4i`, ...), each listed counter-clockwise
//!   (a cell of a surface whose normal is -z is reversed). Physical curves
//!   become node sets and edge (face) sets: each line element is matched
//!   by its end nodes to the edge of a plane cell.
//!
//! Node orders. Gmsh's hexahedron corners equal ours (VTK); the Gmsh
//! reference manual, section "Node ordering"
//! (<https://gmsh.info/doc/texinfo/gmsh.html#Node-ordering>, the
//! `Hexahedron20` / `Hexahedron27` pictures, also reproduced in Gmsh's
//! `Geo/MHexahedron.h`) numbers the mid-edge nodes
//! 8: 0-1, 9: 0-3, 10: 0-4, 11: 1-2, 12: 1-5, 13: 2-3, 14: 2-6, 15: 3-7,
//! 16: 4-5, 17: 4-7, 18: 5-6, 19: 6-7 and the face centres
//! 20: (0,3,2,1) z-, 21: (0,1,5,4) y-, 22: (0,4,7,3) x-, 23: (1,2,6,5) x+,
//! 24: (2,3,7,6) y+, 25: (4,5,6,7) z+, 26: body centre.
//! [`GMSH_TO_OURS_HEX27`] converts; a unit test checks it geometrically
//! against [`junta_core::topology::HEX27_NODES`]. Quadrilaterals (4, 8, 9 nodes)
//! are in our order already.

use junta_core::mesh::{ElementBlock, ElementRef, FaceRef, Mesh};
use junta_core::topology::CellShape;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use thiserror::Error;

/// `ours[i] = gmsh[GMSH_TO_OURS_PRISM15[i]]` (take the first 6 for prism6):
/// Gmsh's corners equal ours (Abaqus'), its mid-edge nodes run 0-1, 0-2,
/// 0-3, 1-2, 1-4, 2-5, 3-4, 3-5, 4-5.
pub const GMSH_TO_OURS_PRISM15: [usize; 15] = [0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11];

/// `ours[i] = gmsh[GMSH_TO_OURS_HEX27[i]]` (take the first 20 for hex20).
pub const GMSH_TO_OURS_HEX27: [usize; 27] = [
    0, 1, 2, 3, 4, 5, 6, 7, // corners
    8, 11, 13, 9, // bottom edges 0-1, 1-2, 2-3, 3-0
    16, 18, 19, 17, // top edges 4-5, 5-6, 6-7, 7-4
    10, 12, 14, 15, // vertical edges 0-4, 1-5, 2-6, 3-7
    22, 23, 21, 24, 20, 25, // faces x-, x+, y-, y+, z-, z+
    26,
];

/// Errors of the Gmsh reader. Every message names the file, and the line
/// where there is one.
#[derive(Debug, Error)]
pub enum GmshError {
    /// The file could not be read.
    #[error("cannot read `{file}`: {source}")]
    Io {
        /// The file, as given.
        file: String,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// Binary MSH files are not supported.
    #[error("{file}:{line}: binary MSH files are not supported; re-export as ASCII (gmsh: `-format msh41` with `Mesh.Binary = 0`)")]
    Binary {
        /// The file, as given.
        file: String,
        /// Line of the `$MeshFormat` data (1-based).
        line: usize,
    },
    /// Only MSH 4.1 is read.
    #[error("{file}:{line}: MSH version `{version}` is not supported; valid: 4.1 (gmsh: `-format msh41`)")]
    Version {
        /// The file, as given.
        file: String,
        /// Line of the `$MeshFormat` data (1-based).
        line: usize,
        /// The version the file declares.
        version: String,
    },
    /// An element type the reader does not handle.
    #[error("{file}:{line}: Gmsh element type {code} is not supported; valid: 5 (hex8), 17 (hex20), 12 (hex27), 3/16/10 (quad4/8/9 boundary faces), 2/9 (tri3/6 boundary faces), 15 (point), 1/8/26 (lines, ignored)")]
    ElementType {
        /// The file, as given.
        file: String,
        /// Line of the element block's header (1-based).
        line: usize,
        /// Gmsh's element type code.
        code: usize,
    },
    /// Malformed content.
    #[error("{file}:{line}: {message}")]
    Syntax {
        /// The file, as given.
        file: String,
        /// Line (1-based; 0 for a fault of the whole mesh, found after
        /// reading).
        line: usize,
        /// What is wrong.
        message: String,
    },
}

/// Read a MSH 4.1 ASCII file.
pub fn read_msh(path: impl AsRef<Path>) -> Result<Mesh, GmshError> {
    let (file, text) = read_text(path.as_ref())?;
    parse_msh(&text, &file)
}

/// The file's name as given and its text.
fn read_text(path: &Path) -> Result<(String, String), GmshError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| GmshError::Io {
        file: file.clone(),
        source,
    })?;
    Ok((file, text))
}

/// A 2D mesh of quadrilaterals and triangles, the base a lay-up is
/// stacked on ([`read_surface`]).
#[derive(Debug, Clone)]
pub struct SurfaceMesh {
    /// Node coordinates (every node of the file).
    pub nodes: Vec<[f64; 3]>,
    /// Second order: Quad8 and Tri6 cells; else Quad4 and Tri3 (one order
    /// per file).
    pub quadratic: bool,
    /// Flat connectivity of the quadrilaterals, our order (Gmsh's): 4 or 8
    /// nodes each.
    pub quads: Vec<usize>,
    /// Flat connectivity of the triangles, our order (Gmsh's): 3 or 6
    /// nodes each.
    pub tris: Vec<usize>,
    /// Physical curves: name -> the corner node pairs of their line elements.
    pub curves: BTreeMap<String, Vec<[usize; 2]>>,
}

impl SurfaceMesh {
    /// `Quad4` or `Quad8`.
    pub fn quad_shape(&self) -> CellShape {
        if self.quadratic {
            CellShape::Quad8
        } else {
            CellShape::Quad4
        }
    }
    /// `Tri3` or `Tri6`.
    pub fn tri_shape(&self) -> CellShape {
        if self.quadratic {
            CellShape::Tri6
        } else {
            CellShape::Tri3
        }
    }
}

/// Read the quadrilaterals (4 or 8 nodes), the triangles (3 or 6 nodes)
/// and the physical curves of a 2D MSH 4.1 ASCII file: the base of a
/// lay-up. Other 2D cells (Quad9), a mix of orders, or a file with no 2D
/// cell are errors naming the line.
pub fn read_surface(path: impl AsRef<Path>) -> Result<SurfaceMesh, GmshError> {
    let (file, text) = read_text(path.as_ref())?;
    let mut c = Cursor {
        lines: text.lines().collect(),
        pos: 0,
        file: &file,
    };
    let mut s = Sections::read(&mut c)?;
    let mut out = SurfaceMesh {
        nodes: std::mem::take(&mut s.nodes),
        quadratic: false,
        quads: Vec::new(),
        tris: Vec::new(),
        curves: BTreeMap::new(),
    };
    let mut order: Option<bool> = None;
    for b in &s.blocks {
        let (sh, npe) = shape_of(b.code).expect("read_elements keeps known codes");
        match b.dim {
            2 => {
                let quadratic = match sh {
                    CellShape::Quad4 | CellShape::Tri3 => false,
                    CellShape::Quad8 | CellShape::Tri6 => true,
                    _ => return Err(c.err(b.line, format!(
                        "a lay-up base takes quadrilaterals of 4 or 8 nodes and triangles of 3 or 6 nodes (Gmsh types 3, 16, 2, 9), not element type {}: use Mesh.ElementOrder 1 or 2 with Mesh.SecondOrderIncomplete = 1",
                        b.code
                    ))),
                };
                if order.is_some_and(|x| x != quadratic) {
                    return Err(c.err(b.line, "cells of two orders in one base (first and second order); mesh it with one Mesh.ElementOrder"));
                }
                order = Some(quadratic);
                let into = if matches!(sh, CellShape::Quad4 | CellShape::Quad8) {
                    &mut out.quads
                } else {
                    &mut out.tris
                };
                for (_, conn) in &b.elements {
                    for &tag in &conn[..npe] {
                        into.push(s.resolve(&c, b.line, tag)?);
                    }
                }
            }
            1 => {
                for g in s.groups_of(1, b.entity) {
                    let name = s.phys_name(1, g);
                    for (_, conn) in &b.elements {
                        let pair = [
                            s.resolve(&c, b.line, conn[0])?,
                            s.resolve(&c, b.line, conn[1])?,
                        ];
                        out.curves.entry(name.clone()).or_default().push(pair);
                    }
                }
            }
            _ => {}
        }
    }
    out.quadratic = order.ok_or_else(|| {
        c.err(
            0,
            "no quadrilateral or triangle in the file: a lay-up base needs a 2D mesh",
        )
    })?;
    Ok(out)
}

/// Line-oriented cursor over the file (1-based line numbers).
struct Cursor<'a> {
    lines: Vec<&'a str>,
    pos: usize,
    file: &'a str,
}

impl<'a> Cursor<'a> {
    fn err(&self, line: usize, message: impl Into<String>) -> GmshError {
        GmshError::Syntax {
            file: self.file.to_string(),
            line,
            message: message.into(),
        }
    }
    /// Check that at least `need` more lines follow before reserving room
    /// for a count read from the file (a header declaring 1e12 entries in a
    /// small file is an error, not an allocation).
    fn enough_lines(
        &self,
        line: usize,
        what: &str,
        count: usize,
        lines_each: usize,
    ) -> Result<(), GmshError> {
        let left = self.lines.len().saturating_sub(self.pos);
        if count.saturating_mul(lines_each) > left {
            return Err(self.err(
                line,
                format!("header declares {count} {what}, but only {left} lines follow"),
            ));
        }
        Ok(())
    }
    /// Next line (trimmed), with its 1-based number.
    fn next(&mut self, what: &str) -> Result<(usize, &'a str), GmshError> {
        if self.pos >= self.lines.len() {
            return Err(self.err(
                self.lines.len(),
                format!("unexpected end of file while reading {what}"),
            ));
        }
        let l = self.lines[self.pos].trim();
        self.pos += 1;
        Ok((self.pos, l))
    }
    /// Next line split in whitespace tokens.
    fn tokens(&mut self, what: &str) -> Result<(usize, Vec<&'a str>), GmshError> {
        let (n, l) = self.next(what)?;
        Ok((n, l.split_whitespace().collect()))
    }
    fn num<T: std::str::FromStr>(
        &self,
        line: usize,
        tok: Option<&&str>,
        what: &str,
    ) -> Result<T, GmshError> {
        let t = tok.ok_or_else(|| self.err(line, format!("missing {what}")))?;
        t.parse()
            .map_err(|_| self.err(line, format!("bad {what} `{t}`")))
    }
    fn expect_end(&mut self, section: &str) -> Result<(), GmshError> {
        let (n, l) = self.next(&format!("$End{section}"))?;
        if l != format!("$End{section}") {
            return Err(self.err(n, format!("expected `$End{section}`, found `{l}`")));
        }
        Ok(())
    }
}

struct ElemBlock {
    dim: usize,
    entity: i64,
    code: usize,
    line: usize,
    /// element tag and node tags (gmsh order)
    elements: Vec<(usize, Vec<usize>)>,
}

fn shape_of(code: usize) -> Option<(CellShape, usize)> {
    match code {
        5 => Some((CellShape::Hex8, 8)),
        17 => Some((CellShape::Hex20, 20)),
        12 => Some((CellShape::Hex27, 27)),
        6 => Some((CellShape::Wedge6, 6)),
        18 => Some((CellShape::Wedge15, 15)),
        3 => Some((CellShape::Quad4, 4)),
        16 => Some((CellShape::Quad8, 8)),
        10 => Some((CellShape::Quad9, 9)),
        2 => Some((CellShape::Tri3, 3)),
        9 => Some((CellShape::Tri6, 6)),
        15 => Some((CellShape::Quad4, 1)), // point: shape unused
        1 => Some((CellShape::Quad4, 2)),
        8 => Some((CellShape::Quad4, 3)),
        26 => Some((CellShape::Quad4, 4)),
        _ => None,
    }
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
/// Right-hand normal of a face given by its corners: a quadrilateral's
/// diagonals crossed, a triangle's first two edges.
fn face_normal(p: &[[f64; 3]]) -> [f64; 3] {
    if p.len() == 3 {
        cross(sub(p[1], p[0]), sub(p[2], p[0]))
    } else {
        cross(sub(p[2], p[0]), sub(p[3], p[1]))
    }
}

/// The sections of a MSH file as read, before the mesh is built.
#[derive(Default)]
struct Sections {
    /// `(dimension, physical tag)` -> name.
    physical_names: HashMap<(usize, i64), String>,
    /// `(dimension, entity tag)` -> its physical groups.
    entity_phys: HashMap<(usize, i64), Vec<i64>>,
    nodes: Vec<[f64; 3]>,
    /// The file's node tags.
    labels: Vec<usize>,
    /// Node tag -> node index.
    node_id: HashMap<usize, usize>,
    blocks: Vec<ElemBlock>,
}

/// Parse the text of a MSH 4.1 ASCII file; `file_name` is used in messages.
/// Reads the sections, then builds the blocks of the volume elements and
/// the node and face sets of the lower-dimensional groups.
pub fn parse_msh(text: &str, file_name: &str) -> Result<Mesh, GmshError> {
    let mut c = Cursor {
        lines: text.lines().collect(),
        pos: 0,
        file: file_name,
    };
    let mut s = Sections::read(&mut c)?;
    let mut mesh = Mesh {
        nodes: std::mem::take(&mut s.nodes),
        node_labels: std::mem::take(&mut s.labels),
        ..Mesh::default()
    };
    volume_blocks(&c, &s, &mut mesh)?;
    if mesh.blocks.is_empty() && s.blocks.iter().any(|b| b.dim == 2) {
        plane_blocks(&c, &s, &mut mesh)?;
    }
    group_sets(&c, &s, &mut mesh)?;
    mesh.validate().map_err(|e| c.err(0, e.to_string()))?;
    Ok(mesh)
}

impl Sections {
    /// Read every section: `$MeshFormat` first, then `$PhysicalNames`,
    /// `$Entities`, `$Nodes` and `$Elements`; other sections are skipped.
    fn read(c: &mut Cursor<'_>) -> Result<Sections, GmshError> {
        let mut s = Sections::default();
        let mut seen_format = false;
        while c.pos < c.lines.len() {
            let (n, l) = c.next("a section")?;
            if l.is_empty() {
                continue;
            }
            match l {
                "$MeshFormat" => {
                    mesh_format(c)?;
                    seen_format = true;
                }
                _ if !seen_format => {
                    return Err(c.err(n, format!("expected `$MeshFormat` first, found `{l}`")));
                }
                "$PhysicalNames" => s.read_physical_names(c)?,
                "$Entities" => s.read_entities(c)?,
                "$Nodes" => s.read_nodes(c)?,
                "$Elements" => s.read_elements(c)?,
                h if h.starts_with('$') && !h.starts_with("$End") => {
                    // skip an unknown section
                    let end = format!("$End{}", &h[1..]);
                    loop {
                        let (_, l) = c.next(&end)?;
                        if l == end {
                            break;
                        }
                    }
                }
                _ => {
                    return Err(c.err(n, format!("expected a section header `$Name`, found `{l}`")))
                }
            }
        }
        if !seen_format {
            return Err(c.err(1, "no `$MeshFormat` section: not a Gmsh MSH file"));
        }
        Ok(s)
    }

    /// `$PhysicalNames`: `dim tag "name"` lines.
    fn read_physical_names(&mut self, c: &mut Cursor<'_>) -> Result<(), GmshError> {
        let (ln, t) = c.tokens("$PhysicalNames")?;
        let count: usize = c.num(ln, t.first(), "number of physical names")?;
        for _ in 0..count {
            let (ln, l) = c.next("a physical name")?;
            let mut it = l.splitn(3, char::is_whitespace);
            let dim: usize = c.num(ln, it.next().as_ref(), "physical dimension")?;
            let tag: i64 = c.num(ln, it.next().as_ref(), "physical tag")?;
            let name = it.next().unwrap_or("").trim().trim_matches('"').to_string();
            self.physical_names.insert((dim, tag), name);
        }
        c.expect_end("PhysicalNames")
    }

    /// `$Entities`: the physical groups of each point, curve, surface and
    /// volume entity.
    fn read_entities(&mut self, c: &mut Cursor<'_>) -> Result<(), GmshError> {
        let (ln, t) = c.tokens("$Entities")?;
        let mut counts = [0usize; 4];
        for (d, cnt) in counts.iter_mut().enumerate() {
            *cnt = c.num(ln, t.get(d), "entity count")?;
        }
        c.enough_lines(
            ln,
            "entities",
            counts.iter().fold(0usize, |a, &b| a.saturating_add(b)),
            1,
        )?;
        for (dim, &cnt) in counts.iter().enumerate() {
            for _ in 0..cnt {
                let (ln, t) = c.tokens("an entity")?;
                let tag: i64 = c.num(ln, t.first(), "entity tag")?;
                // points: tag x y z nPhys ...; others: tag 6 bbox values nPhys ...
                let at = if dim == 0 { 4 } else { 7 };
                let np: usize = c.num(ln, t.get(at), "number of physical tags")?;
                if np > t.len() {
                    return Err(c.err(
                        ln,
                        format!(
                            "{np} physical tags declared, {} values on the line",
                            t.len()
                        ),
                    ));
                }
                let mut phys = Vec::with_capacity(np);
                for k in 0..np {
                    let p: i64 = c.num(ln, t.get(at + 1 + k), "physical tag")?;
                    phys.push(p.abs());
                }
                self.entity_phys.insert((dim, tag), phys);
            }
        }
        c.expect_end("Entities")
    }

    /// `$Nodes`: blocks of node tags followed by their coordinates (a tag
    /// defined twice is an error).
    fn read_nodes(&mut self, c: &mut Cursor<'_>) -> Result<(), GmshError> {
        let (ln, t) = c.tokens("$Nodes")?;
        let nblocks: usize = c.num(ln, t.first(), "number of node blocks")?;
        let total: usize = c.num(ln, t.get(1), "number of nodes")?;
        c.enough_lines(ln, "node blocks", nblocks, 1)?;
        c.enough_lines(ln, "nodes", total, 2)?;
        self.nodes.reserve(total);
        self.labels.reserve(total);
        for _ in 0..nblocks {
            let (ln, t) = c.tokens("a node block")?;
            let _parametric: usize = c.num(ln, t.get(2), "parametric flag")?;
            let count: usize = c.num(ln, t.get(3), "number of nodes in block")?;
            c.enough_lines(ln, "nodes", count, 2)?;
            let mut tags = Vec::with_capacity(count);
            for _ in 0..count {
                let (ln, t) = c.tokens("a node tag")?;
                tags.push((ln, c.num::<usize>(ln, t.first(), "node tag")?));
            }
            for (tln, tag) in tags {
                let (ln, t) = c.tokens("node coordinates")?;
                // parametric nodes (flag != 0) carry u [v [w]] after x y z: ignored
                if t.len() < 3 {
                    return Err(c.err(ln, "expected x y z"));
                }
                let mut x = [0.0; 3];
                for (d, xd) in x.iter_mut().enumerate() {
                    *xd = c.num(ln, t.get(d), "coordinate")?;
                }
                if self.node_id.insert(tag, self.nodes.len()).is_some() {
                    return Err(c.err(tln, format!("node tag {tag} defined twice")));
                }
                self.nodes.push(x);
                self.labels.push(tag);
            }
        }
        c.expect_end("Nodes")
    }

    /// `$Elements`: blocks of elements of one type on one entity (element
    /// tag and node tags, Gmsh order).
    fn read_elements(&mut self, c: &mut Cursor<'_>) -> Result<(), GmshError> {
        let (ln, t) = c.tokens("$Elements")?;
        let nblocks: usize = c.num(ln, t.first(), "number of element blocks")?;
        c.enough_lines(ln, "element blocks", nblocks, 1)?;
        for _ in 0..nblocks {
            let (ln, t) = c.tokens("an element block")?;
            let dim: usize = c.num(ln, t.first(), "entity dimension")?;
            let entity: i64 = c.num(ln, t.get(1), "entity tag")?;
            let code: usize = c.num(ln, t.get(2), "element type")?;
            let count: usize = c.num(ln, t.get(3), "number of elements")?;
            c.enough_lines(ln, "elements", count, 1)?;
            let (_, npe) = shape_of(code).ok_or_else(|| GmshError::ElementType {
                file: c.file.into(),
                line: ln,
                code,
            })?;
            let mut b = ElemBlock {
                dim,
                entity,
                code,
                line: ln,
                elements: Vec::with_capacity(count),
            };
            for _ in 0..count {
                let (eln, t) = c.tokens("an element")?;
                if t.len() != npe + 1 {
                    return Err(c.err(
                        eln,
                        format!(
                            "element of type {code} needs a tag and {npe} nodes, found {} values",
                            t.len()
                        ),
                    ));
                }
                let tag: usize = c.num(eln, t.first(), "element tag")?;
                let mut conn = Vec::with_capacity(npe);
                for k in 0..npe {
                    conn.push(c.num::<usize>(eln, t.get(k + 1), "node tag")?);
                }
                b.elements.push((tag, conn));
            }
            self.blocks.push(b);
        }
        c.expect_end("Elements")
    }

    /// Element `r` into the element set of each physical group `groups`
    /// of dimension `dim`.
    fn add_to_groups(
        &self,
        sets: &mut BTreeMap<String, Vec<ElementRef>>,
        dim: usize,
        groups: &[i64],
        r: ElementRef,
    ) {
        for &g in groups {
            sets.entry(self.phys_name(dim, g)).or_default().push(r);
        }
    }

    /// Name of a physical group (`physical<dim>d_<tag>` when unnamed).
    fn phys_name(&self, dim: usize, tag: i64) -> String {
        self.physical_names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| format!("physical{dim}d_{tag}"))
    }

    /// Physical groups of an entity.
    fn groups_of(&self, dim: usize, entity: i64) -> Vec<i64> {
        self.entity_phys
            .get(&(dim, entity))
            .cloned()
            .unwrap_or_default()
    }

    /// Node index of a node tag.
    fn resolve(&self, c: &Cursor, line: usize, tag: usize) -> Result<usize, GmshError> {
        self.node_id
            .get(&tag)
            .copied()
            .ok_or_else(|| c.err(line, format!("element refers to undefined node tag {tag}")))
    }
}

/// `$MeshFormat`: version 4.1, ASCII.
fn mesh_format(c: &mut Cursor<'_>) -> Result<(), GmshError> {
    let (ln, t) = c.tokens("$MeshFormat")?;
    let version = t.first().copied().unwrap_or("");
    let ftype = t.get(1).copied().unwrap_or("");
    if ftype == "1" {
        return Err(GmshError::Binary {
            file: c.file.into(),
            line: ln,
        });
    }
    if version != "4.1" {
        return Err(GmshError::Version {
            file: c.file.into(),
            line: ln,
            version: version.into(),
        });
    }
    if ftype != "0" {
        return Err(c.err(ln, format!("bad file type `{ftype}`; valid: 0 (ASCII)")));
    }
    c.expect_end("MeshFormat")
}

/// Volume elements -> blocks: one per physical volume and shape (named
/// after the group, `volume<tag>` outside any group, `<name>_<shape>` for a
/// second shape), connectivity in our node order, element labels, and one
/// element set per physical volume.
fn volume_blocks(c: &Cursor, s: &Sections, mesh: &mut Mesh) -> Result<(), GmshError> {
    let mut block_index: HashMap<(String, CellShape), usize> = HashMap::new();
    let mut element_sets: BTreeMap<String, Vec<ElementRef>> = BTreeMap::new();
    for b in s.blocks.iter().filter(|b| b.dim == 3) {
        let (shape, npe) = shape_of(b.code).unwrap();
        if !shape.is_solid() {
            return Err(c.err(
                b.line,
                format!("element type {} is not a volume element", b.code),
            ));
        }
        let groups = s.groups_of(3, b.entity);
        let name = match groups.first() {
            Some(&g) => s.phys_name(3, g),
            None => format!("volume{}", b.entity),
        };
        let key = (name.clone(), shape);
        let bi = match block_index.get(&key) {
            Some(&i) => i,
            None => {
                let taken = mesh.blocks.iter().any(|x| x.name == name);
                let bname = if taken {
                    format!("{name}_{}", shape.name())
                } else {
                    name.clone()
                };
                mesh.blocks.push(ElementBlock {
                    name: bname,
                    shape,
                    connectivity: Vec::new(),
                    element_type: match shape {
                        CellShape::Hex8 => "h8",
                        CellShape::Hex20 => "h20",
                        CellShape::Wedge6 => "wedge6",
                        CellShape::Wedge15 => "wedge15",
                        _ => "h27",
                    }
                    .into(),
                    material: if groups.is_empty() {
                        String::new()
                    } else {
                        name.clone()
                    },
                });
                block_index.insert(key, mesh.blocks.len() - 1);
                mesh.blocks.len() - 1
            }
        };
        for (tag, conn) in &b.elements {
            let e = mesh.blocks[bi].len();
            // the mesh file's element tags (Mesh::element_labels)
            mesh.element_labels.resize(mesh.blocks.len(), Vec::new());
            mesh.element_labels[bi].push(*tag);
            let order: &[usize] = match shape {
                CellShape::Wedge6 | CellShape::Wedge15 => &GMSH_TO_OURS_PRISM15[..npe],
                _ => &GMSH_TO_OURS_HEX27[..npe],
            };
            for &k in order {
                let id = s.resolve(c, b.line, conn[k])?;
                mesh.blocks[bi].connectivity.push(id);
            }
            s.add_to_groups(
                &mut element_sets,
                3,
                &groups,
                ElementRef {
                    block: bi,
                    element: e,
                },
            );
        }
    }
    mesh.element_sets = element_sets;
    Ok(())
}

/// The plane cell and default element type of a 2D Gmsh element code.
fn plane_kind(code: usize) -> Option<(CellShape, &'static str)> {
    match code {
        3 => Some((CellShape::PlaneQuad4, "cpe4")),
        16 => Some((CellShape::PlaneQuad8, "cpe8")),
        10 => Some((CellShape::PlaneQuad9, "cpe9")),
        2 => Some((CellShape::PlaneTri3, "cpe3")),
        9 => Some((CellShape::PlaneTri6, "cpe6")),
        _ => None,
    }
}

/// The node order of a plane cell listed clockwise, turned
/// counter-clockwise: corners reversed from the first, mid-side nodes
/// with them (`order[i]` is the given position of our node `i`).
fn counter_clockwise(shape: CellShape) -> &'static [usize] {
    match shape {
        CellShape::PlaneTri3 => &[0, 2, 1],
        CellShape::PlaneTri6 => &[0, 2, 1, 5, 4, 3],
        CellShape::PlaneQuad4 => &[0, 3, 2, 1],
        CellShape::PlaneQuad8 => &[0, 3, 2, 1, 7, 6, 5, 4],
        _ => &[0, 3, 2, 1, 7, 6, 5, 4, 8],
    }
}

/// Surface elements of a 2D mesh -> blocks of plane cells, one per
/// physical surface and shape (named as [`volume_blocks`] names its
/// blocks), counter-clockwise, with an element set per physical surface.
fn plane_blocks(c: &Cursor, s: &Sections, mesh: &mut Mesh) -> Result<(), GmshError> {
    if let Some(i) = mesh.nodes.iter().position(|x| x[2].abs() > 0.0) {
        return Err(c.err(
            0,
            format!(
                "a 2D mesh (surface elements only) is a plane model in the x-y plane, but node {} lies at z = {}",
                mesh.node_labels.get(i).copied().unwrap_or(i + 1),
                mesh.nodes[i][2]
            ),
        ));
    }
    let mut block_index: HashMap<(String, CellShape), usize> = HashMap::new();
    let mut element_sets: BTreeMap<String, Vec<ElementRef>> = BTreeMap::new();
    for b in s.blocks.iter().filter(|b| b.dim == 2) {
        let (shape, etype) = plane_kind(b.code).ok_or_else(|| {
            c.err(
                b.line,
                format!("element type {} cannot lie on a surface", b.code),
            )
        })?;
        let groups = s.groups_of(2, b.entity);
        let name = match groups.first() {
            Some(&g) => s.phys_name(2, g),
            None => format!("surface{}", b.entity),
        };
        let bi = *block_index.entry((name.clone(), shape)).or_insert_with(|| {
            let taken = mesh.blocks.iter().any(|x| x.name == name);
            mesh.blocks.push(ElementBlock {
                name: if taken {
                    format!("{name}_{}", shape.name())
                } else {
                    name.clone()
                },
                shape,
                connectivity: Vec::new(),
                element_type: etype.into(),
                material: if groups.is_empty() {
                    String::new()
                } else {
                    name.clone()
                },
            });
            mesh.blocks.len() - 1
        });
        for (tag, conn) in &b.elements {
            let ids: Vec<usize> = conn
                .iter()
                .map(|&t| s.resolve(c, b.line, t))
                .collect::<Result<_, _>>()?;
            let p: Vec<[f64; 3]> = ids
                .iter()
                .take(shape.num_faces())
                .map(|&i| mesh.nodes[i])
                .collect();
            let ccw = face_normal(&p)[2] > 0.0;
            let e = mesh.blocks[bi].len();
            mesh.element_labels.resize(mesh.blocks.len(), Vec::new());
            mesh.element_labels[bi].push(*tag);
            let order: Vec<usize> = if ccw {
                (0..ids.len()).collect()
            } else {
                counter_clockwise(shape).to_vec()
            };
            mesh.blocks[bi]
                .connectivity
                .extend(order.iter().map(|&k| ids[k]));
            s.add_to_groups(
                &mut element_sets,
                2,
                &groups,
                ElementRef {
                    block: bi,
                    element: e,
                },
            );
        }
    }
    mesh.element_sets = element_sets;
    Ok(())
}

/// Lower-dimensional physical groups -> node sets (all nodes of their
/// elements), and for surfaces also face sets: each quadrangle or triangle
/// is matched by its corners to a face of a volume element
/// ([`surface_face`]).
fn group_sets(c: &Cursor, s: &Sections, mesh: &mut Mesh) -> Result<(), GmshError> {
    // faces of volume elements keyed by sorted corner nodes
    let mut faces: HashMap<[usize; 4], Vec<FaceRef>> = HashMap::new();
    for (bi, b) in mesh.blocks.iter().enumerate() {
        for e in 0..b.len() {
            for f in 0..b.shape.num_faces() {
                let r = FaceRef {
                    block: bi,
                    element: e,
                    face: f,
                };
                // triangles (wedge ends) have keys padded with usize::MAX
                // and never match a quadrangle of a surface group
                if let Some(key) = mesh.face_key(r) {
                    faces.entry(key).or_default().push(r);
                }
            }
        }
    }
    let mut node_sets: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    let mut face_sets: BTreeMap<String, Vec<FaceRef>> = BTreeMap::new();
    // a plane mesh: its surfaces are its cells, its curves their edges
    let plane = mesh.blocks.iter().any(|b| b.shape.is_plane());
    for b in s
        .blocks
        .iter()
        .filter(|b| b.dim < 3 && !(plane && b.dim == 2))
    {
        let groups = s.groups_of(b.dim, b.entity);
        if groups.is_empty() {
            continue;
        }
        // corners of a surface element: quadrangles 4, triangles 3; of a
        // line (the edge of a plane cell) 2
        let corners = match b.code {
            3 | 16 | 10 => 4,
            2 | 9 => 3,
            1 | 8 | 26 if plane => 2,
            _ => 0,
        };
        if b.dim == 2 && corners == 0 {
            return Err(c.err(
                b.line,
                format!("element type {} cannot lie on a surface", b.code),
            ));
        }
        for (tag, conn) in &b.elements {
            let ids: Vec<usize> = conn
                .iter()
                .map(|&t| s.resolve(c, b.line, t))
                .collect::<Result<_, _>>()?;
            let face = match (b.dim, plane) {
                (2, false) => Some(surface_face(c, mesh, &faces, b, *tag, &ids[..corners])?),
                (1, true) => Some(surface_face(c, mesh, &faces, b, *tag, &ids[..corners])?),
                _ => None,
            };
            for &g in &groups {
                let name = s.phys_name(b.dim, g);
                node_sets
                    .entry(name.clone())
                    .or_default()
                    .extend(ids.iter().copied());
                if let Some(f) = face {
                    face_sets.entry(name).or_default().push(f);
                }
            }
        }
    }
    for v in node_sets.values_mut() {
        v.sort_unstable();
        v.dedup();
    }
    mesh.node_sets = node_sets;
    mesh.face_sets = face_sets;
    Ok(())
}

/// The volume face under surface element `tag` of block `b`, whose corner
/// node indices are `corners`: the face with the same corners (the face
/// key of [`Mesh::face_key`]: sorted corners, a triangle's padded with
/// `usize::MAX`); of two (an internal surface), the one whose outward
/// normal agrees with the surface element's right-hand normal.
fn surface_face(
    c: &Cursor,
    mesh: &Mesh,
    faces: &HashMap<[usize; 4], Vec<FaceRef>>,
    b: &ElemBlock,
    tag: usize,
    corners: &[usize],
) -> Result<FaceRef, GmshError> {
    let n = corners.len();
    let mut key = [usize::MAX; 4];
    key[..n].copy_from_slice(corners);
    key.sort_unstable();
    let what = match n {
        4 => "quadrangle",
        3 => "triangle",
        _ => "line",
    };
    let cands = faces.get(&key).ok_or_else(|| {
        let hint = match n {
            3 => " (triangles match the end faces of wedge elements)",
            2 => " (a line of a 2D mesh matches the edge of one of its quadrangles or triangles)",
            _ => "",
        };
        c.err(
            b.line,
            format!(
                "{what} {tag} of {} {} is not {}{hint}",
                if n == 2 { "curve" } else { "surface" },
                b.entity,
                if n == 2 {
                    "an edge of any plane cell"
                } else {
                    "a face of any volume element"
                }
            ),
        )
    })?;
    if n == 2 {
        // an edge of a plane mesh: on the boundary it has one cell
        return Ok(cands[0]);
    }
    let p: Vec<[f64; 3]> = corners.iter().map(|&i| mesh.nodes[i]).collect();
    let nq = face_normal(&p);
    let pick = cands
        .iter()
        .find(|&&f| {
            let fnodes = mesh.face_nodes(f);
            let q: Vec<[f64; 3]> = fnodes[..n].iter().map(|&i| mesh.nodes[i]).collect();
            dot(face_normal(&q), nq) > 0.0
        })
        .unwrap_or(&cands[0]);
    Ok(*pick)
}

#[cfg(test)]
mod tests {
    use super::*;
    use junta_core::topology::HEX27_NODES;

    /// Natural coordinates of the 27 Gmsh hexahedron nodes, written from the
    /// manual's picture (not from our table).
    fn gmsh_hex27_coords() -> Vec<[f64; 3]> {
        let c = [
            [-1., -1., -1.],
            [1., -1., -1.],
            [1., 1., -1.],
            [-1., 1., -1.],
            [-1., -1., 1.],
            [1., -1., 1.],
            [1., 1., 1.],
            [-1., 1., 1.],
        ];
        let mid = |a: usize, b: usize| -> [f64; 3] {
            [
                0.5 * (c[a][0] + c[b][0]),
                0.5 * (c[a][1] + c[b][1]),
                0.5 * (c[a][2] + c[b][2]),
            ]
        };
        let face = |q: [usize; 4]| -> [f64; 3] {
            let mut s = [0.0; 3];
            for &i in &q {
                for d in 0..3 {
                    s[d] += 0.25 * c[i][d];
                }
            }
            s
        };
        let mut v: Vec<[f64; 3]> = c.to_vec();
        let edges = [
            (0, 1),
            (0, 3),
            (0, 4),
            (1, 2),
            (1, 5),
            (2, 3),
            (2, 6),
            (3, 7),
            (4, 5),
            (4, 7),
            (5, 6),
            (6, 7),
        ];
        for (a, b) in edges {
            v.push(mid(a, b));
        }
        for q in [
            [0, 3, 2, 1],
            [0, 1, 5, 4],
            [0, 4, 7, 3],
            [1, 2, 6, 5],
            [2, 3, 7, 6],
            [4, 5, 6, 7],
        ] {
            v.push(face(q));
        }
        v.push([0.0; 3]);
        v
    }

    #[test]
    fn gmsh_permutation_is_geometric() {
        let g = gmsh_hex27_coords();
        for (i, &k) in GMSH_TO_OURS_HEX27.iter().enumerate() {
            assert_eq!(g[k], HEX27_NODES[i], "our node {i} <- gmsh node {k}");
        }
        let mut seen = GMSH_TO_OURS_HEX27.to_vec();
        seen.sort_unstable();
        assert_eq!(seen, (0..27).collect::<Vec<_>>());
        // hex20: the first 20 entries only use gmsh nodes 0..20
        assert!(GMSH_TO_OURS_HEX27[..20].iter().all(|&k| k < 20));
    }

    #[test]
    fn prism15_order_maps_to_ours_geometrically() {
        use junta_core::topology::WEDGE15_NODES;
        // Gmsh's reference prism: corners as ours, edges 0-1, 0-2, 0-3, 1-2,
        // 1-4, 2-5, 3-4, 3-5, 4-5 (Gmsh manual, node ordering)
        let mut g: Vec<[f64; 3]> = WEDGE15_NODES[..6].to_vec();
        for (a, b) in [
            (0, 1),
            (0, 2),
            (0, 3),
            (1, 2),
            (1, 4),
            (2, 5),
            (3, 4),
            (3, 5),
            (4, 5),
        ] {
            g.push([0, 1, 2].map(|d| 0.5 * (g[a][d] + g[b][d])));
        }
        for (i, &k) in GMSH_TO_OURS_PRISM15.iter().enumerate() {
            assert_eq!(g[k], WEDGE15_NODES[i], "our node {i}");
        }
    }
}
