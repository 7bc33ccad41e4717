//! Cell shapes, their node orders and faces: the one place where node
//! numbering is defined. Every other crate (shape functions, generators,
//! readers, writers) follows these tables; conversions to Gmsh or Abaqus
//! orders live in the readers, to VTK in the writer (our order *is* VTK's
//! for hexahedra, so the writer needs no permutation).
//!
//! ```text
//! Hexahedra (H8 / H20 / H27), natural coordinates (xi, eta, zeta) in [-1, 1]^3
//!
//!         7 ------14------ 6          corners 0..7     (VTK, Abaqus C3D8)
//!        /|               /|          mid-edges 8..19  (VTK, Abaqus C3D20):
//!      15 |    25       13 |            8:0-1  9:1-2 10:2-3 11:3-0
//!      /  19    23     /   18           12:4-5 13:5-6 14:6-7 15:7-4
//!     4 ------12------ 5   |            16:0-4 17:1-5 18:2-6 19:3-7
//!     | 20|     26     | 21|          face centres 20..25 (VTK order):
//!     |   3 ------10---|-- 2            20:x-  21:x+  22:y-  23:y+  24:z-  25:z+
//!    16  /    22      17  /           body centre 26
//!     | 11     24      | 9     zeta
//!     |/               |/      |  eta
//!     0 ------ 8------ 1       | /
//!                              |/___ xi
//! ```
//!
//! Quadrilaterals (Q4 / Q8 / Q9), natural coordinates (xi, eta) in [-1, 1]^2:
//! corners 0 (-1,-1), 1 (1,-1), 2 (1,1), 3 (-1,1); mid-sides 4: 0-1, 5: 1-2,
//! 6: 2-3, 7: 3-0; centre 8. The face normal is V_xi x V_eta (right-hand rule).
//!
//! Triangles (Tri3 / Tri6), natural coordinates (r, s) with r, s >= 0,
//! r + s <= 1 (the bottom triangle of [`WEDGE15_NODES`]): corners 0 (0,0),
//! 1 (1,0), 2 (0,1); mid-edges 3: 0-1, 4: 1-2, 5: 2-0 ([`TRI6_NODES`]). The
//! face normal is V_r x V_s (right-hand rule on 0-1-2).
//!
//! ```text
//!   s
//!   |
//!   2
//!   | \
//!   5   4
//!   |     \
//!   0 --3-- 1 --- r
//! ```
//!
//! Hexahedron faces are listed in Abaqus order S1..S6 (z-, z+, y-, x+, y+, x-),
//! each as a quadrilateral whose right-hand normal points *out* of the cell.
//! Wedge faces are listed in Abaqus / CalculiX order S1..S5 (bottom
//! triangle, top triangle, then the sides 1-2-5-4, 2-3-6-5, 3-1-4-6 in the
//! manuals' 1-based labels), each a triangle or quadrilateral whose
//! right-hand normal points out of the cell ([`WEDGE_FACES`]).
//!
//! Interface cells: the nodes of the bottom face then those of the top
//! face, each in the face's order (quadrilateral for INTER8 / INTER16 /
//! INTER18, triangle for INTER6 / INTER12); the normal points from bottom
//! to top.
//!
//! ## Plane cells (2D: plane strain, plane stress, axisymmetric)
//!
//! The plane solids lie in the x-y plane (for axisymmetric ones x is the
//! radius r and y the axis z): [`CellShape::PlaneQuad4`], `PlaneQuad8`,
//! `PlaneQuad9` in the quadrilateral order above, [`CellShape::PlaneTri3`],
//! `PlaneTri6` in the triangle order above (Abaqus CPE4 / CPE8 / CPE3 /
//! CPE6 orders), counter-clockwise. Their faces are their edges, in Abaqus
//! order S1..S4 (S1..S3 for triangles): edge `k` runs from corner `k` to
//! corner `k + 1`, with its mid-side node last ([`QUAD_EDGES`],
//! [`TRI_EDGES`]); in a counter-clockwise cell the outward normal of an
//! edge with tangent `t` is `(t_y, -t_x)`.
//!
//! Lines ([`CellShape::Line2`], [`CellShape::Line3`]): natural coordinate
//! xi in [-1, 1], end nodes 0 (xi = -1) and 1 (xi = 1), then the middle
//! node 2 (xi = 0), as VTK's quadratic edge.
//!
//! Line interfaces ([`CellShape::LineInter4`], [`CellShape::LineInter6`]):
//! the nodes of the bottom line then those of the top line, each in the
//! line's order; the normal points from bottom to top: with `t` the bottom
//! line's tangent from node 0 to node 1, `n = t x e_z = (t_y, -t_x)` (the
//! right of the line: the outward normal of the edge of a counter-clockwise
//! cell below it, as a solid's face normal points out of it). Abaqus's
//! COH2D4 is counter-clockwise (1-2-3-4, the top on the left of 1-2, node 4
//! above node 1): the deck reader takes it as 2-1-3-4.

/// Every cell shape Junta knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellShape {
    /// 4-node bilinear quadrilateral (a face of Hex8, a side of INTER8).
    Quad4,
    /// 8-node serendipity quadrilateral (a face of Hex20, a side of INTER16).
    Quad8,
    /// 9-node biquadratic quadrilateral (a face of Hex27, a side of INTER18).
    Quad9,
    /// 8-node trilinear hexahedron (VTK, Abaqus C3D8 order).
    Hex8,
    /// 20-node serendipity hexahedron (VTK, Abaqus C3D20 order).
    Hex20,
    /// 27-node triquadratic hexahedron (VTK order; see [`HEX27_NODES`]).
    Hex27,
    /// 8-node interface (two Quad4 sides: bottom 0-3, top copies 4-7);
    /// matches the faces of Hex8 and the quadrilateral sides of Wedge6.
    Inter8,
    /// 16-node interface (two Quad8 sides: bottom 0-7, top copies 8-15);
    /// matches the faces of Hex20 and the quadrilateral sides of Wedge15.
    Inter16,
    /// 18-node interface (two Quad9 sides: bottom 0-8, top copies 9-17);
    /// matches the faces of Hex27 (the paper's element).
    Inter18,
    /// 3-node linear triangle (a wedge face, or a side of INTER6).
    Tri3,
    /// 6-node quadratic triangle (a Wedge15 face, or a side of INTER12).
    Tri6,
    /// 6-node interface (two Tri3 sides: bottom 0-2, top copies 3-5);
    /// matches the triangular faces of Wedge6 (Abaqus COH3D6).
    Inter6,
    /// 12-node interface (two Tri6 sides: bottom 0-5, top copies 6-11);
    /// matches the triangular faces of Wedge15.
    Inter12,
    /// 6-node linear wedge (pentahedron), Abaqus / CalculiX C3D6 order.
    Wedge6,
    /// 15-node serendipity wedge, Abaqus / CalculiX C3D15 order.
    Wedge15,
    /// 2-node line (an edge of a linear plane cell, a side of LINE_INTER4).
    Line2,
    /// 3-node line (an edge of a quadratic plane cell, a side of LINE_INTER6).
    Line3,
    /// 4-node plane quadrilateral (CPE4 / CPS4 / CAX4), Quad4 order.
    PlaneQuad4,
    /// 8-node plane serendipity quadrilateral (CPE8 / CPS8 / CAX8).
    PlaneQuad8,
    /// 9-node plane Lagrange quadrilateral (Quad9 order).
    PlaneQuad9,
    /// 3-node plane triangle (CPE3 / CPS3 / CAX3), Tri3 order.
    PlaneTri3,
    /// 6-node plane triangle (CPE6 / CPS6 / CAX6), Tri6 order.
    PlaneTri6,
    /// 4-node line interface (two Line2 sides: bottom 0-1, top copies 2-3),
    /// between the edges of linear plane cells (Abaqus COH2D4 / COHAX4).
    LineInter4,
    /// 6-node line interface (two Line3 sides: bottom 0-2, top copies 3-5),
    /// between the edges of quadratic plane cells.
    LineInter6,
}

/// Edges of the plane quadrilaterals (Abaqus S1..S4), each as its two
/// corners then its mid-side node (take the first 2 for PlaneQuad4): the
/// outward normal of a counter-clockwise cell is on the right of each.
pub const QUAD_EDGES: [[usize; 3]; 4] = [[0, 1, 4], [1, 2, 5], [2, 3, 6], [3, 0, 7]];

/// Edges of the plane triangles (Abaqus S1..S3), as [`QUAD_EDGES`].
pub const TRI_EDGES: [[usize; 3]; 3] = [[0, 1, 3], [1, 2, 4], [2, 0, 5]];

/// Natural coordinates `(r, s, zeta)` of the 15 wedge nodes (the first 6
/// serve Wedge6), Abaqus / CalculiX order: the triangle `r, s >= 0,
/// r + s <= 1` at `zeta = -1` (nodes 0, 1, 2: (0,0), (1,0), (0,1)), the same
/// at `zeta = +1` (3, 4, 5), bottom mid-edges 6: 0-1, 7: 1-2, 8: 2-0, top
/// mid-edges 9: 3-4, 10: 4-5, 11: 5-3, vertical mid-edges 12: 0-3, 13: 1-4,
/// 14: 2-5. The bottom triangle's right-hand normal points into the cell
/// (towards the top triangle), as for Abaqus. VTK's wedge has the opposite
/// orientation: the writer maps with [`WEDGE15_TO_VTK`].
pub const WEDGE15_NODES: [[f64; 3]; 15] = [
    [0.0, 0.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [0.5, 0.0, -1.0],
    [0.5, 0.5, -1.0],
    [0.0, 0.5, -1.0],
    [0.5, 0.0, 1.0],
    [0.5, 0.5, 1.0],
    [0.0, 0.5, 1.0],
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
];

/// VTK cell node `k` is Junta (Abaqus) wedge node `WEDGE15_TO_VTK[k]` (take
/// the first 6 for Wedge6): VTK lists the triangle 0-1-2 with its normal
/// pointing out of the cell, so nodes 1 and 2 (4 and 5) swap and the
/// mid-edge nodes follow.
pub const WEDGE15_TO_VTK: [usize; 15] = [0, 2, 1, 3, 5, 4, 8, 7, 6, 11, 10, 9, 12, 14, 13];

/// Natural coordinates `(r, s)` of the 6 triangle nodes (the first 3 serve
/// Tri3): the bottom triangle of [`WEDGE15_NODES`] (nodes 0, 1, 2, 6, 7, 8).
pub const TRI6_NODES: [[f64; 2]; 6] = [
    [0.0, 0.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [0.5, 0.0],
    [0.5, 0.5],
    [0.0, 0.5],
];

/// Wedge faces (Abaqus / CalculiX S1..S5), each as local node ids with
/// outward right-hand normal: triangles in Tri6 order (take the first 3 for
/// Wedge6), quadrilaterals in Q8 order (take the first 4 for Wedge6).
///
/// ```text
/// S1 bottom  0-2-1  (Abaqus 1-2-3; reversed: its right-hand normal points in)
/// S2 top     3-4-5  (4-5-6)
/// S3 side    0-1-4-3  (1-2-5-4, the face s = 0)
/// S4 side    1-2-5-4  (2-3-6-5, the face r + s = 1)
/// S5 side    2-0-3-5  (3-1-4-6, the face r = 0)
/// ```
pub const WEDGE_FACES: [&[usize]; 5] = [
    &[0, 2, 1, 8, 7, 6],
    &[3, 4, 5, 9, 10, 11],
    &[0, 1, 4, 3, 6, 13, 9, 12],
    &[1, 2, 5, 4, 7, 14, 10, 13],
    &[2, 0, 3, 5, 8, 12, 11, 14],
];

/// Natural coordinates of the 27 hexahedron nodes (the first 8 / 20 serve H8 / H20).
pub const HEX27_NODES: [[f64; 3]; 27] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [-1.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, -1.0],
    [0.0, 0.0, 1.0],
    [0.0, 0.0, 0.0],
];

/// Natural coordinates of the 9 quadrilateral nodes (first 4 / 8 serve Q4 / Q8).
pub const QUAD9_NODES: [[f64; 2]; 9] = [
    [-1.0, -1.0],
    [1.0, -1.0],
    [1.0, 1.0],
    [-1.0, 1.0],
    [0.0, -1.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [-1.0, 0.0],
    [0.0, 0.0],
];

/// Hexahedron faces (Abaqus S1..S6), each as 9 local node ids in Q9 order
/// with outward right-hand normal. Take the first 4 / 8 for H8 / H20.
pub const HEX_FACES: [[usize; 9]; 6] = [
    [0, 3, 2, 1, 11, 10, 9, 8, 24],   // S1 z-
    [4, 5, 6, 7, 12, 13, 14, 15, 25], // S2 z+
    [0, 1, 5, 4, 8, 17, 12, 16, 22],  // S3 y-
    [1, 2, 6, 5, 9, 18, 13, 17, 21],  // S4 x+
    [2, 3, 7, 6, 10, 19, 14, 18, 23], // S5 y+
    [3, 0, 4, 7, 11, 16, 15, 19, 20], // S6 x-
];

/// Names of the hexahedron faces in [`HEX_FACES`] order (axis-aligned in a
/// box generated with the natural axes along x, y, z).
pub const HEX_FACE_NAMES: [&str; 6] = ["z0", "z1", "y0", "x1", "y1", "x0"];

impl CellShape {
    /// Number of nodes.
    pub fn num_nodes(self) -> usize {
        match self {
            CellShape::Quad4 => 4,
            CellShape::Quad8 => 8,
            CellShape::Quad9 => 9,
            CellShape::Hex8 => 8,
            CellShape::Hex20 => 20,
            CellShape::Hex27 => 27,
            CellShape::Inter8 => 8,
            CellShape::Inter16 => 16,
            CellShape::Inter18 => 18,
            CellShape::Tri3 => 3,
            CellShape::Tri6 => 6,
            CellShape::Inter6 => 6,
            CellShape::Inter12 => 12,
            CellShape::Wedge6 => 6,
            CellShape::Wedge15 => 15,
            CellShape::Line2 => 2,
            CellShape::Line3 => 3,
            CellShape::PlaneQuad4 => 4,
            CellShape::PlaneQuad8 => 8,
            CellShape::PlaneQuad9 => 9,
            CellShape::PlaneTri3 => 3,
            CellShape::PlaneTri6 => 6,
            CellShape::LineInter4 => 4,
            CellShape::LineInter6 => 6,
        }
    }

    /// True for the continuum shapes: the 3D solids and the plane cells
    /// (whose faces are their edges).
    pub fn is_solid(self) -> bool {
        matches!(
            self,
            CellShape::Hex8
                | CellShape::Hex20
                | CellShape::Hex27
                | CellShape::Wedge6
                | CellShape::Wedge15
        ) || self.is_plane()
    }

    /// True for the plane (2D) continuum cells.
    pub fn is_plane(self) -> bool {
        matches!(
            self,
            CellShape::PlaneQuad4
                | CellShape::PlaneQuad8
                | CellShape::PlaneQuad9
                | CellShape::PlaneTri3
                | CellShape::PlaneTri6
        )
    }

    /// The dimension of the space the cell's model lives in: 2 for plane
    /// cells, line interfaces and lines, 3 otherwise.
    pub fn dimension(self) -> usize {
        match self {
            CellShape::Line2 | CellShape::Line3 | CellShape::LineInter4 | CellShape::LineInter6 => {
                2
            }
            s if s.is_plane() => 2,
            _ => 3,
        }
    }

    /// The surface shape with the same node order and natural coordinates
    /// as a plane cell (its shape functions): `PlaneQuad4` -> `Quad4`, ...,
    /// `PlaneTri6` -> `Tri6`; `None` for other shapes.
    pub fn plane_reference(self) -> Option<CellShape> {
        match self {
            CellShape::PlaneQuad4 => Some(CellShape::Quad4),
            CellShape::PlaneQuad8 => Some(CellShape::Quad8),
            CellShape::PlaneQuad9 => Some(CellShape::Quad9),
            CellShape::PlaneTri3 => Some(CellShape::Tri3),
            CellShape::PlaneTri6 => Some(CellShape::Tri6),
            _ => None,
        }
    }

    /// True for the zero-thickness interface shapes.
    pub fn is_interface(self) -> bool {
        matches!(
            self,
            CellShape::Inter8
                | CellShape::Inter16
                | CellShape::Inter18
                | CellShape::Inter6
                | CellShape::Inter12
                | CellShape::LineInter4
                | CellShape::LineInter6
        )
    }

    /// True for the surface shapes (quadrilaterals and triangles).
    pub fn is_surface(self) -> bool {
        matches!(
            self,
            CellShape::Quad4
                | CellShape::Quad8
                | CellShape::Quad9
                | CellShape::Tri3
                | CellShape::Tri6
        )
    }

    /// The shape of every face of a hexahedron, or of each side of an
    /// interface. `None` for wedges (whose faces have two shapes: see
    /// [`CellShape::face_shape_of`]) and for surfaces.
    pub fn face_shape(self) -> Option<CellShape> {
        match self {
            CellShape::Hex8 | CellShape::Inter8 => Some(CellShape::Quad4),
            CellShape::Hex20 | CellShape::Inter16 => Some(CellShape::Quad8),
            CellShape::Hex27 | CellShape::Inter18 => Some(CellShape::Quad9),
            CellShape::Inter6 => Some(CellShape::Tri3),
            CellShape::Inter12 => Some(CellShape::Tri6),
            CellShape::PlaneQuad4 | CellShape::PlaneTri3 | CellShape::LineInter4 => {
                Some(CellShape::Line2)
            }
            CellShape::PlaneQuad8
            | CellShape::PlaneQuad9
            | CellShape::PlaneTri6
            | CellShape::LineInter6 => Some(CellShape::Line3),
            _ => None,
        }
    }

    /// The shape of face `f` of a solid (`None` if `f >= num_faces()` or
    /// the shape is not a solid): quadrilaterals for hexahedra; for wedges
    /// triangles (S1, S2) and quadrilaterals (S3..S5).
    pub fn face_shape_of(self, f: usize) -> Option<CellShape> {
        if f >= self.num_faces() {
            return None;
        }
        match self {
            CellShape::Wedge6 if f < 2 => Some(CellShape::Tri3),
            CellShape::Wedge6 => Some(CellShape::Quad4),
            CellShape::Wedge15 if f < 2 => Some(CellShape::Tri6),
            CellShape::Wedge15 => Some(CellShape::Quad8),
            s => s.face_shape(),
        }
    }

    /// Number of faces of a solid: 6 for hexahedra, 5 for wedges, the
    /// edges of a plane cell (4 or 3), 0 for other shapes.
    pub fn num_faces(self) -> usize {
        match self {
            CellShape::Hex8 | CellShape::Hex20 | CellShape::Hex27 => 6,
            CellShape::Wedge6 | CellShape::Wedge15 => 5,
            CellShape::PlaneQuad4 | CellShape::PlaneQuad8 | CellShape::PlaneQuad9 => 4,
            CellShape::PlaneTri3 | CellShape::PlaneTri6 => 3,
            _ => 0,
        }
    }

    /// Local node ids of face `f` in its face shape's order, outward normal
    /// ([`HEX_FACES`], [`WEDGE_FACES`]). Empty for non-solids and for
    /// `f >= num_faces()`.
    pub fn face_nodes(self, f: usize) -> &'static [usize] {
        match (self, self.face_shape_of(f)) {
            (CellShape::Wedge6 | CellShape::Wedge15, Some(q)) => &WEDGE_FACES[f][..q.num_nodes()],
            (CellShape::PlaneTri3 | CellShape::PlaneTri6, Some(q)) => {
                &TRI_EDGES[f][..q.num_nodes()]
            }
            (s, Some(q)) if s.is_plane() => &QUAD_EDGES[f][..q.num_nodes()],
            (_, Some(q)) => &HEX_FACES[f][..q.num_nodes()],
            _ => &[],
        }
    }

    /// Number of corner nodes of a surface shape (3 or 4) or a line (2; 0
    /// otherwise). Corners come first in every node order.
    pub fn num_corners(self) -> usize {
        match self {
            CellShape::Tri3 | CellShape::Tri6 => 3,
            CellShape::Quad4 | CellShape::Quad8 | CellShape::Quad9 => 4,
            CellShape::Line2 | CellShape::Line3 => 2,
            _ => 0,
        }
    }

    /// The interface shape that matches a face shape (`Quad4` -> `Inter8`,
    /// `Quad8` -> `Inter16`, `Quad9` -> `Inter18`, `Tri3` -> `Inter6`,
    /// `Tri6` -> `Inter12`), or a solid by its principal faces: hexahedra
    /// by their quadrilaterals (`Hex8` -> `Inter8`, ...), wedges by their
    /// triangles (`Wedge6` -> `Inter6`, `Wedge15` -> `Inter12`: the faces
    /// between wedge layers; a wedge's quadrilateral sides match `Inter8` /
    /// `Inter16`, see [`CellShape::face_shape_of`]).
    pub fn matching_interface(self) -> Option<CellShape> {
        match self {
            CellShape::Hex8 | CellShape::Quad4 => Some(CellShape::Inter8),
            CellShape::Hex20 | CellShape::Quad8 => Some(CellShape::Inter16),
            CellShape::Hex27 | CellShape::Quad9 => Some(CellShape::Inter18),
            CellShape::Wedge6 | CellShape::Tri3 => Some(CellShape::Inter6),
            CellShape::Wedge15 | CellShape::Tri6 => Some(CellShape::Inter12),
            CellShape::Line2 => Some(CellShape::LineInter4),
            CellShape::Line3 => Some(CellShape::LineInter6),
            _ => None,
        }
    }

    /// VTK cell type id (our node order equals VTK's for all shapes but the
    /// wedges, see [`WEDGE15_TO_VTK`]). Interfaces are written as their
    /// mid-surface (one point per node pair), so their type is that of
    /// their side: VTK_QUAD (9), VTK_QUADRATIC_QUAD (23),
    /// VTK_BIQUADRATIC_QUAD (28), VTK_TRIANGLE (5), VTK_QUADRATIC_TRIANGLE
    /// (22; corners then mid-edges 0-1, 1-2, 2-0, as ours), VTK_LINE (3),
    /// VTK_QUADRATIC_EDGE (21; ends then middle, as ours). Plane cells are
    /// the quadrilaterals and triangles of the same orders.
    pub fn vtk_type(self) -> u8 {
        match self {
            CellShape::Quad4 | CellShape::Inter8 => 9,
            CellShape::Quad8 | CellShape::Inter16 => 23,
            CellShape::Quad9 | CellShape::Inter18 => 28,
            CellShape::Tri3 | CellShape::Inter6 => 5,
            CellShape::Tri6 | CellShape::Inter12 => 22,
            CellShape::Hex8 => 12,
            CellShape::Hex20 => 25,
            CellShape::Hex27 => 29,
            CellShape::Wedge6 => 13,
            CellShape::Wedge15 => 26,
            CellShape::Line2 | CellShape::LineInter4 => 3,
            CellShape::Line3 | CellShape::LineInter6 => 21,
            CellShape::PlaneQuad4 => 9,
            CellShape::PlaneQuad8 => 23,
            CellShape::PlaneQuad9 => 28,
            CellShape::PlaneTri3 => 5,
            CellShape::PlaneTri6 => 22,
        }
    }

    /// Lower-case name used in scenes and messages.
    pub fn name(self) -> &'static str {
        match self {
            CellShape::Quad4 => "quad4",
            CellShape::Quad8 => "quad8",
            CellShape::Quad9 => "quad9",
            CellShape::Hex8 => "hex8",
            CellShape::Hex20 => "hex20",
            CellShape::Hex27 => "hex27",
            CellShape::Inter8 => "inter8",
            CellShape::Inter16 => "inter16",
            CellShape::Inter18 => "inter18",
            CellShape::Tri3 => "tri3",
            CellShape::Tri6 => "tri6",
            CellShape::Inter6 => "inter6",
            CellShape::Inter12 => "inter12",
            CellShape::Wedge6 => "wedge6",
            CellShape::Wedge15 => "wedge15",
            CellShape::Line2 => "line2",
            CellShape::Line3 => "line3",
            CellShape::PlaneQuad4 => "plane_quad4",
            CellShape::PlaneQuad8 => "plane_quad8",
            CellShape::PlaneQuad9 => "plane_quad9",
            CellShape::PlaneTri3 => "plane_tri3",
            CellShape::PlaneTri6 => "plane_tri6",
            CellShape::LineInter4 => "line_inter4",
            CellShape::LineInter6 => "line_inter6",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
    fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    /// Wedge faces: outward normals (the face centre minus the cell centre
    /// has a positive component along it), mid-edge nodes at midpoints,
    /// face shapes and counts, and Tri6 = the wedge's bottom triangle.
    #[test]
    fn wedge_faces_point_outward_and_midnodes_are_midpoints() {
        let centre = [1.0 / 3.0, 1.0 / 3.0, 0.0];
        for s in [CellShape::Wedge6, CellShape::Wedge15] {
            assert_eq!(s.num_faces(), 5);
            assert_eq!(s.face_nodes(5), &[] as &[usize]);
            assert_eq!(s.face_shape_of(5), None);
        }
        for (f, face) in WEDGE_FACES.iter().enumerate() {
            let q = CellShape::Wedge15.face_shape_of(f).unwrap();
            let k = q.num_corners();
            assert_eq!(face.len(), 2 * k);
            assert_eq!(CellShape::Wedge15.face_nodes(f), *face);
            assert_eq!(CellShape::Wedge6.face_nodes(f), &face[..k]);
            let p: Vec<[f64; 3]> = face.iter().map(|&i| WEDGE15_NODES[i]).collect();
            let n = cross(sub(p[1], p[0]), sub(p[k - 1], p[0]));
            let mut c = [0.0; 3];
            for x in &p[..k] {
                for d in 0..3 {
                    c[d] += x[d] / k as f64;
                }
            }
            let out = sub(c, centre);
            let dot = n[0] * out[0] + n[1] * out[1] + n[2] * out[2];
            assert!(dot > 0.0, "face {face:?} normal {n:?} not outward");
            for j in 0..k {
                let (a, b, m) = (p[j], p[(j + 1) % k], p[k + j]);
                for d in 0..3 {
                    assert_eq!(m[d], 0.5 * (a[d] + b[d]), "face {face:?} mid-edge {j}");
                }
            }
        }
        for (a, &w) in [0, 1, 2, 6, 7, 8].iter().enumerate() {
            assert_eq!(TRI6_NODES[a], [WEDGE15_NODES[w][0], WEDGE15_NODES[w][1]]);
        }
        assert_eq!(
            CellShape::Wedge6.matching_interface(),
            Some(CellShape::Inter6)
        );
        assert_eq!(
            CellShape::Wedge15.matching_interface(),
            Some(CellShape::Inter12)
        );
        assert_eq!(CellShape::Inter6.face_shape(), Some(CellShape::Tri3));
        assert_eq!(CellShape::Inter12.face_shape(), Some(CellShape::Tri6));
        assert_eq!(CellShape::Inter12.num_nodes(), 12);
        assert!(CellShape::Inter6.is_interface() && !CellShape::Tri3.is_interface());
        assert!(CellShape::LineInter4.is_interface() && CellShape::LineInter6.is_interface());
        assert_eq!(
            CellShape::Line3.matching_interface(),
            Some(CellShape::LineInter6)
        );
        assert_eq!(
            CellShape::PlaneQuad8.face_shape_of(3),
            Some(CellShape::Line3)
        );
        assert_eq!(CellShape::PlaneQuad8.face_nodes(3), &[3, 0, 7]);
        assert_eq!(CellShape::PlaneTri6.face_nodes(2), &[2, 0, 5]);
        assert!(CellShape::PlaneTri3.is_solid() && CellShape::PlaneTri3.dimension() == 2);
    }

    #[test]
    fn hex_faces_point_outward_and_midnodes_are_midpoints() {
        for face in HEX_FACES {
            let p: Vec<[f64; 3]> = face.iter().map(|&i| HEX27_NODES[i]).collect();
            let n = cross(sub(p[1], p[0]), sub(p[3], p[0]));
            // centre of the face is the outward direction of the unit cube
            let c = p[8];
            let dot = n[0] * c[0] + n[1] * c[1] + n[2] * c[2];
            assert!(dot > 0.0, "face {face:?} normal {n:?} not outward");
            for k in 0..4 {
                let a = p[k];
                let b = p[(k + 1) % 4];
                let m = p[4 + k];
                for d in 0..3 {
                    assert_eq!(m[d], 0.5 * (a[d] + b[d]), "face {face:?} mid-side {k}");
                }
            }
        }
    }
}
