//! Integration tests of `mesh::merge` and `mesh::interface`: merging box
//! parts and inserting zero-thickness interfaces between them.

use junta_core::mesh::generate::{box_mesh, BoxSpec};
use junta_core::mesh::interface::{insert_interface, interface_pairs};
use junta_core::mesh::merge::merge;
use junta_core::mesh::Mesh;
use junta_core::topology::CellShape;
use std::collections::HashSet;

const SHAPES: [CellShape; 3] = [CellShape::Hex8, CellShape::Hex20, CellShape::Hex27];

fn boxm(origin: [f64; 3], size: [f64; 3], div: [usize; 3], shape: CellShape) -> Mesh {
    let mut s = BoxSpec::new(size, div, shape);
    s.origin = origin;
    box_mesh(&s, "block", shape.name(), "steel").unwrap()
}

/// Node count of an n x n x n box (closed forms of the generator).
fn cube_nodes(shape: CellShape, n: usize) -> usize {
    match shape {
        CellShape::Hex8 => (n + 1).pow(3),
        CellShape::Hex20 => (n + 1).pow(3) + 3 * n * (n + 1).pow(2),
        CellShape::Hex27 => (2 * n + 1).pow(3),
        _ => unreachable!(),
    }
}

/// Node count of an n x n face.
fn face_nodes(shape: CellShape, n: usize) -> usize {
    match shape {
        CellShape::Hex8 => (n + 1).pow(2),
        CellShape::Hex20 => (n + 1).pow(2) + 2 * n * (n + 1),
        CellShape::Hex27 => (2 * n + 1).pow(2),
        _ => unreachable!(),
    }
}

fn stacked(shape: CellShape) -> Mesh {
    let lower = boxm([0.0; 3], [1.0, 1.0, 0.5], [2, 2, 1], shape);
    let upper = boxm([0.0, 0.0, 0.5], [1.0, 1.0, 0.5], [2, 2, 1], shape);
    merge(vec![("lower".into(), lower), ("upper".into(), upper)], 1e-8).unwrap()
}

/// Nodes used by the elements of an element set.
fn nodes_of_set(mesh: &Mesh, set: &str) -> HashSet<usize> {
    mesh.element_set(set)
        .unwrap()
        .iter()
        .flat_map(|r| mesh.blocks[r.block].element(r.element).to_vec())
        .collect()
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

/// Unit normal of interface element `e` of block `b` from its first three
/// bottom corners (right-hand rule).
fn normal(mesh: &Mesh, b: usize, e: usize) -> [f64; 3] {
    let c = mesh.blocks[b].element(e);
    let p = |i: usize| mesh.nodes[c[i]];
    let n = cross(sub(p(1), p(0)), sub(p(2), p(0)));
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    n.map(|x| x / l)
}

#[test]
fn stacked_boxes_merge_and_get_an_interface() {
    for shape in SHAPES {
        let mut m = stacked(shape);
        let box_count = cube_nodes(shape, 2);
        assert_eq!(m.nodes.len(), box_count, "{shape:?} merged node count");
        assert_eq!(m.blocks.len(), 2);
        assert_eq!(m.blocks[0].name, "lower");
        assert_eq!(m.element_sets["upper"].len(), 4);
        assert!(m.node_sets.contains_key("lower.z0"));
        // the shared face is one set of nodes, seen from both parts
        assert_eq!(m.node_sets["lower.z1"], m.node_sets["upper.z0"]);

        let ins = insert_interface(&mut m, "lower", "upper", "glue", "penalty").unwrap();
        assert_eq!(ins.elements, 4);
        assert_eq!(ins.block, 2);
        let ib = &m.blocks[ins.block];
        assert_eq!(Some(ib.shape), shape.matching_interface());
        assert_eq!(ib.element_type, ib.shape.name());
        assert_eq!(ib.material, "penalty");
        assert_eq!(ins.duplicated_nodes, face_nodes(shape, 2), "{shape:?}");
        assert_eq!(m.nodes.len(), box_count + face_nodes(shape, 2));
        m.validate().unwrap();

        let lower_nodes = nodes_of_set(&m, "lower");
        let upper_nodes = nodes_of_set(&m, "upper");
        let half = ib.nodes_per_element() / 2;
        for e in 0..ib.len() {
            let c = ib.element(e);
            for i in 0..half {
                let (b, t) = (c[i], c[half + i]);
                assert_ne!(b, t);
                assert_eq!(m.nodes[b], m.nodes[t]);
                assert_eq!(m.nodes[b][2], 0.5);
                assert!(lower_nodes.contains(&b) && !upper_nodes.contains(&b));
                assert!(upper_nodes.contains(&t) && !lower_nodes.contains(&t));
            }
            let n = normal(&m, ins.block, e);
            assert!((n[2] - 1.0).abs() < 1e-12, "{shape:?} normal {n:?}");
        }
        // new sets
        assert_eq!(m.element_sets["glue"].len(), 4);
        assert_eq!(m.node_sets["glue.bottom"].len(), ins.duplicated_nodes);
        assert_eq!(m.node_sets["glue.top"].len(), ins.duplicated_nodes);
        let pairs = interface_pairs(&m, ins.block);
        assert_eq!(pairs.len(), ins.duplicated_nodes);
        assert!(pairs
            .iter()
            .all(|&(b, t)| m.nodes[b] == m.nodes[t] && b != t));
        // node-set rule: the top part's sets follow the copies, the bottom's stay
        assert_eq!(m.node_sets["upper.z0"], m.node_sets["glue.top"]);
        assert_eq!(m.node_sets["lower.z1"], m.node_sets["glue.bottom"]);
    }
}

#[test]
fn lateral_contact_normal_points_along_x() {
    for shape in SHAPES {
        let left = boxm([0.0; 3], [0.5, 1.0, 1.0], [1, 2, 2], shape);
        let right = boxm([0.5, 0.0, 0.0], [0.5, 1.0, 1.0], [1, 2, 2], shape);
        let mut m = merge(vec![("left".into(), left), ("right".into(), right)], 1e-8).unwrap();
        let ins = insert_interface(&mut m, "left", "right", "i", "law").unwrap();
        assert_eq!(ins.elements, 4);
        for e in 0..ins.elements {
            let n = normal(&m, ins.block, e);
            assert!((n[0] - 1.0).abs() < 1e-12, "{shape:?} normal {n:?}");
        }
        // swapping the sides flips the normal
        let left = boxm([0.0; 3], [0.5, 1.0, 1.0], [1, 2, 2], shape);
        let right = boxm([0.5, 0.0, 0.0], [0.5, 1.0, 1.0], [1, 2, 2], shape);
        let mut m = merge(vec![("left".into(), left), ("right".into(), right)], 1e-8).unwrap();
        let ins = insert_interface(&mut m, "right", "left", "i", "law").unwrap();
        assert!((normal(&m, ins.block, 0)[0] + 1.0).abs() < 1e-12);
    }
}

#[test]
fn sets_sharing_no_face_are_rejected() {
    // far apart
    let a = boxm([0.0; 3], [1.0; 3], [1; 3], CellShape::Hex8);
    let b = boxm([5.0, 0.0, 0.0], [1.0; 3], [1; 3], CellShape::Hex8);
    let mut m = merge(vec![("a".into(), a), ("b".into(), b)], 1e-8).unwrap();
    let before = m.clone();
    let err = insert_interface(&mut m, "a", "b", "i", "law")
        .unwrap_err()
        .to_string();
    assert!(err.contains("`a`") && err.contains("`b`"), "{err}");
    assert!(err.contains("share no face"), "{err}");
    assert!(err.contains("no node in common"), "{err}");
    assert_eq!(
        m, before,
        "a failed insertion must leave the mesh unchanged"
    );

    // touching along an edge (x = 1, z = 1) only
    let a = boxm([0.0; 3], [1.0; 3], [2; 3], CellShape::Hex20);
    let b = boxm([1.0, 0.0, 1.0], [1.0; 3], [2; 3], CellShape::Hex20);
    let mut m = merge(vec![("a".into(), a), ("b".into(), b)], 1e-8).unwrap();
    let err = insert_interface(&mut m, "a", "b", "i", "law")
        .unwrap_err()
        .to_string();
    assert!(err.contains("share no face"), "{err}");
    // the shared edge holds 2 elements' worth of quadratic nodes: 5 nodes
    assert!(err.contains("touch at 5 node(s) only"), "{err}");
}

#[test]
fn mismatched_orders_are_rejected() {
    for (sa, sb) in [
        (CellShape::Hex20, CellShape::Hex27),
        (CellShape::Hex8, CellShape::Hex20),
    ] {
        let a = boxm([0.0; 3], [1.0, 1.0, 0.5], [2, 2, 1], sa);
        let b = boxm([0.0, 0.0, 0.5], [1.0, 1.0, 0.5], [2, 2, 1], sb);
        let mut m = merge(vec![("a".into(), a), ("b".into(), b)], 1e-8).unwrap();
        let err = insert_interface(&mut m, "a", "b", "i", "law")
            .unwrap_err()
            .to_string();
        let want = format!(
            "mismatched element orders across `a`/`b`: {} faces against {} faces",
            sa.name(),
            sb.name()
        );
        assert!(err.contains(&want), "{err}");
        assert!(err.contains("same solid order on both sides"), "{err}");
    }
}

#[test]
fn third_body_stays_on_the_bottom_side() {
    for shape in SHAPES {
        let lower = boxm([0.0; 3], [1.0, 1.0, 0.5], [2, 2, 1], shape);
        let upper = boxm([0.0, 0.0, 0.5], [1.0, 1.0, 0.5], [2, 2, 1], shape);
        let side = boxm([1.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2, 2, 2], shape);
        let mut m = merge(
            vec![
                ("lower".into(), lower),
                ("upper".into(), upper),
                ("side".into(), side),
            ],
            1e-8,
        )
        .unwrap();
        let side_before = m.blocks[2].connectivity.clone();
        let ins = insert_interface(&mut m, "lower", "upper", "glue", "law").unwrap();
        assert_eq!(m.blocks[2].connectivity, side_before, "{shape:?}");
        // the side body shares the surface's edge nodes at x = 1 with the
        // bottom side, not with the top copies
        let side_nodes = nodes_of_set(&m, "side");
        let pairs = interface_pairs(&m, ins.block);
        let on_edge: Vec<_> = pairs
            .iter()
            .filter(|&&(b, _)| m.nodes[b][0] == 1.0)
            .collect();
        assert_eq!(on_edge.len(), if shape == CellShape::Hex8 { 3 } else { 5 });
        for &&(b, t) in &on_edge {
            assert!(side_nodes.contains(&b) && !side_nodes.contains(&t));
        }
        // the side body's own node set stays with the nodes the body uses
        let s = &m.node_sets["side.x0"];
        assert!(on_edge
            .iter()
            .all(|&&(b, t)| s.contains(&b) && !s.contains(&t)));
        // the top part's set at x = 1 follows the copies, the bottom's does not
        assert!(on_edge.iter().all(|&&(b, t)| {
            let (u, l) = (&m.node_sets["upper.x1"], &m.node_sets["lower.x1"]);
            u.contains(&t) && !u.contains(&b) && l.contains(&b) && !l.contains(&t)
        }));
    }
}

#[test]
fn neutral_node_sets_hold_both_sides() {
    let mut m = stacked(CellShape::Hex27);
    // a symmetry plane x = 0 through both parts, named after no element set
    let plane: Vec<usize> = (0..m.nodes.len())
        .filter(|&i| m.nodes[i][0] == 0.0)
        .collect();
    m.node_sets.insert("symmetry".into(), plane.clone());
    let ins = insert_interface(&mut m, "lower", "upper", "glue", "law").unwrap();
    let s = &m.node_sets["symmetry"];
    // x = 0 edge of the surface: 5 nodes, each with its copy
    assert_eq!(s.len(), plane.len() + 5);
    for (b, t) in interface_pairs(&m, ins.block) {
        if m.nodes[b][0] == 0.0 {
            assert!(s.contains(&b) && s.contains(&t));
        }
    }
    assert!(s.windows(2).all(|w| w[0] < w[1]), "sorted and unique");
}

#[test]
fn merge_tolerance() {
    let lower = || boxm([0.0; 3], [1.0, 1.0, 0.5], [2, 2, 1], CellShape::Hex8);
    let upper = |dz: f64| {
        boxm(
            [0.0, 0.0, 0.5 + dz],
            [1.0, 1.0, 0.5],
            [2, 2, 1],
            CellShape::Hex8,
        )
    };
    let m = merge(
        vec![("l".into(), lower()), ("u".into(), upper(1e-12))],
        1e-8,
    )
    .unwrap();
    assert_eq!(m.nodes.len(), 27);
    // a merge never moves nodes: the shared nodes keep the lower part's z
    assert!(m.node_sets["u.z0"].iter().all(|&i| m.nodes[i][2] == 0.5));
    let m = merge(vec![("l".into(), lower()), ("u".into(), upper(1e-3))], 1e-8).unwrap();
    assert_eq!(m.nodes.len(), 36);
    assert!(m.node_sets["u.z0"]
        .iter()
        .all(|&i| m.nodes[i][2] == 0.5 + 1e-3));
    // with a tolerance above the gap (1e-3 / diagonal ~ 5.8e-4) they merge
    let m = merge(vec![("l".into(), lower()), ("u".into(), upper(1e-3))], 1e-3).unwrap();
    assert_eq!(m.nodes.len(), 27);
}

#[test]
fn merge_of_larger_quadratic_boxes() {
    let n = [10, 10, 5];
    let a = boxm([0.0; 3], [1.0, 1.0, 0.5], n, CellShape::Hex27);
    let b = boxm([0.0, 0.0, 0.5], [1.0, 1.0, 0.5], n, CellShape::Hex27);
    let mut m = merge(vec![("a".into(), a), ("b".into(), b)], 1e-8).unwrap();
    assert_eq!(m.nodes.len(), 21 * 21 * 21);
    let ins = insert_interface(&mut m, "a", "b", "i", "law").unwrap();
    assert_eq!(ins.elements, 100);
    assert_eq!(ins.duplicated_nodes, 21 * 21);
    assert_eq!(m.nodes.len(), 21 * 21 * 22);
}

// ------------------------------------------------------------ wedges

/// Two wedge layers (2 x 2 cells, 8 wedges each) stacked in z share 8
/// triangles: INTER6 / INTER12 elements in
/// the bottom wedges' S2 order (normal +z), the whole triangulated surface
/// duplicated once ((n + 1)^2 nodes for Wedge6, (2n + 1)^2 for Wedge15: the
/// cut's mid-nodes included), node sets by the usual rule.
#[test]
fn wedge_layers_get_triangular_interfaces() {
    for (shape, ishape, surface) in [
        (CellShape::Wedge6, CellShape::Inter6, 9),
        (CellShape::Wedge15, CellShape::Inter12, 25),
    ] {
        let mut m = stacked(shape);
        let before = m.nodes.len();
        let ins = insert_interface(&mut m, "lower", "upper", "glue", "penalty").unwrap();
        assert_eq!(ins.elements, 8, "{shape:?}");
        let ib = &m.blocks[ins.block];
        assert_eq!(ib.shape, ishape);
        assert_eq!(Some(ishape), shape.matching_interface());
        assert_eq!(ib.element_type, ishape.name());
        assert_eq!(ins.duplicated_nodes, surface, "{shape:?}");
        assert_eq!(m.nodes.len(), before + surface);
        m.validate().unwrap();
        let (lower, upper) = (nodes_of_set(&m, "lower"), nodes_of_set(&m, "upper"));
        let half = ib.nodes_per_element() / 2;
        for e in 0..ib.len() {
            let c = ib.element(e);
            for i in 0..half {
                let (b, t) = (c[i], c[half + i]);
                assert_ne!(b, t);
                assert_eq!(m.nodes[b], m.nodes[t]);
                assert_eq!(m.nodes[b][2], 0.5);
                assert!(lower.contains(&b) && !upper.contains(&b));
                assert!(upper.contains(&t) && !lower.contains(&t));
            }
            // triangle order: corners then mid-edges 0-1, 1-2, 2-0
            if half == 6 {
                for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                    for d in 0..3 {
                        let mid = 0.5 * (m.nodes[c[i]][d] + m.nodes[c[j]][d]);
                        assert!((m.nodes[c[3 + k]][d] - mid).abs() < 1e-15);
                    }
                }
            }
            let n = normal(&m, ins.block, e);
            assert!((n[2] - 1.0).abs() < 1e-12, "{shape:?} normal {n:?}");
        }
        assert_eq!(m.node_sets["upper.z0"], m.node_sets["glue.top"]);
        assert_eq!(m.node_sets["lower.z1"], m.node_sets["glue.bottom"]);
        assert_eq!(interface_pairs(&m, ins.block).len(), surface);
    }
}

/// Solids side by side in x share quadrilaterals: a wedge's side against a
/// wedge's side, or against a hexahedron's face of the same order, gets
/// INTER8 (Quad4) / INTER16 (Quad8) with normal +x; a Wedge15 side (Q8)
/// against a Hex27 face (Q9) is a mismatch of orders.
#[test]
fn wedge_sides_get_quadrilateral_interfaces() {
    for (left, right, ishape) in [
        (CellShape::Wedge6, CellShape::Wedge6, CellShape::Inter8),
        (CellShape::Hex8, CellShape::Wedge6, CellShape::Inter8),
        (CellShape::Wedge15, CellShape::Wedge15, CellShape::Inter16),
        (CellShape::Wedge15, CellShape::Hex20, CellShape::Inter16),
    ] {
        let a = boxm([0.0; 3], [0.5, 1.0, 1.0], [1, 2, 2], left);
        let b = boxm([0.5, 0.0, 0.0], [0.5, 1.0, 1.0], [1, 2, 2], right);
        let mut m = merge(vec![("left".into(), a), ("right".into(), b)], 1e-8).unwrap();
        let ins = insert_interface(&mut m, "left", "right", "i", "law").unwrap();
        let name = format!("{left:?}/{right:?}");
        assert_eq!(m.blocks[ins.block].shape, ishape, "{name}");
        assert_eq!(ins.elements, 4, "{name}");
        for e in 0..ins.elements {
            let n = normal(&m, ins.block, e);
            assert!((n[0] - 1.0).abs() < 1e-12, "{name}: normal {n:?}");
        }
        assert_eq!(m.node_sets["right.x0"], m.node_sets["i.top"], "{name}");
    }
    let a = boxm([0.0; 3], [0.5, 1.0, 1.0], [1, 2, 2], CellShape::Wedge15);
    let b = boxm(
        [0.5, 0.0, 0.0],
        [0.5, 1.0, 1.0],
        [1, 2, 2],
        CellShape::Hex27,
    );
    let mut m = merge(vec![("a".into(), a), ("b".into(), b)], 1e-8).unwrap();
    let err = insert_interface(&mut m, "a", "b", "i", "law")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("mismatched element orders") && err.contains("quad8 against quad9"),
        "{err}"
    );
}

/// A surface of triangles (wedges on wedges) and quadrilaterals (hexahedra
/// on hexahedra) side by side gets two interface blocks on one surface:
/// `glue` (INTER8 on the quadrilateral) and `glue.tri` (INTER6 on the two
/// triangles), the element set `glue` holding all three, every surface
/// node (the seam's included) duplicated once and every top element moved
/// to the copies, so the two sides are apart everywhere but through the
/// interface.
#[test]
fn mixed_triangle_and_quadrilateral_surface_gets_one_block_per_shape() {
    let parts = vec![
        (
            "lw".to_string(),
            boxm([0.0; 3], [1.0, 1.0, 0.5], [1, 1, 1], CellShape::Wedge6),
        ),
        (
            "lh".to_string(),
            boxm([1.0, 0.0, 0.0], [1.0, 1.0, 0.5], [1, 1, 1], CellShape::Hex8),
        ),
        (
            "uw".to_string(),
            boxm(
                [0.0, 0.0, 0.5],
                [1.0, 1.0, 0.5],
                [1, 1, 1],
                CellShape::Wedge6,
            ),
        ),
        (
            "uh".to_string(),
            boxm([1.0, 0.0, 0.5], [1.0, 1.0, 0.5], [1, 1, 1], CellShape::Hex8),
        ),
    ];
    let mut m = merge(parts, 1e-8).unwrap();
    for (set, a, b) in [("lower", "lw", "lh"), ("upper", "uw", "uh")] {
        let mut v = m.element_sets[a].clone();
        v.extend(m.element_sets[b].iter().copied());
        m.element_sets.insert(set.into(), v);
    }
    let nodes_before = m.nodes.len();
    let ins = insert_interface(&mut m, "lower", "upper", "glue", "law").unwrap();
    assert_eq!(ins.blocks.len(), 2);
    assert_eq!(ins.block, ins.blocks[0]);
    let (q, t) = (&m.blocks[ins.blocks[0]], &m.blocks[ins.blocks[1]]);
    assert_eq!(
        (q.name.as_str(), q.shape, q.len()),
        ("glue", CellShape::Inter8, 1)
    );
    assert_eq!(
        (t.name.as_str(), t.shape, t.len()),
        ("glue.tri", CellShape::Inter6, 2)
    );
    assert_eq!(ins.elements, 3);
    assert_eq!(m.element_sets["glue"].len(), 3);
    // the surface z = 0.5: x in {0, 1, 2}, y in {0, 1}
    assert_eq!(ins.duplicated_nodes, 6);
    assert_eq!(m.nodes.len(), nodes_before + 6);
    let copies: std::collections::HashSet<usize> = (nodes_before..m.nodes.len()).collect();
    let originals: std::collections::HashSet<usize> =
        m.node_sets["glue.bottom"].iter().copied().collect();
    for set in ["uw", "uh"] {
        for r in &m.element_sets[set] {
            let conn = m.blocks[r.block].element(r.element);
            assert!(
                conn.iter().all(|n| !originals.contains(n)),
                "{set}: {conn:?}"
            );
            assert!(conn.iter().any(|n| copies.contains(n)), "{set}: {conn:?}");
        }
    }
    for set in ["lw", "lh"] {
        for r in &m.element_sets[set] {
            let conn = m.blocks[r.block].element(r.element);
            assert!(conn.iter().all(|n| !copies.contains(n)), "{set}: {conn:?}");
        }
    }
    // each interface element: bottom side originals, top side their copies
    for b in [q, t] {
        let half = b.nodes_per_element() / 2;
        for e in 0..b.len() {
            let c = b.element(e);
            for k in 0..half {
                assert!(originals.contains(&c[k]) && copies.contains(&c[half + k]));
                assert_eq!(m.nodes[c[k]], m.nodes[c[half + k]]);
            }
        }
    }
}
