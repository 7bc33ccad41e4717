//! `junta run --export-matrix DIR`: the linear system of a model in Matrix
//! Market format, for other solvers (pyamg, PETSc, MUMPS):
//!
//! * `K.mtx`: the assembled stiffness of the free dofs at the prescribed
//!   displacements of load factor 1 (coordinate, real, symmetric: the upper
//!   triangle, as `sprs` writes it; readers mirror it);
//! * `b.mtx`: the right-hand side of the first solve, `f_ext - f_int(u_0)`
//!   on the free dofs (array, `n x 1`);
//! * `B.mtx`: the near-null space the AMG back end uses, the six rigid-body
//!   modes (translations x, y, z, rotations about x, y, z) at each equation
//!   (array, `n x 6`, column-major);
//! * `layout.csv`: per equation its node, component (0..2), body and
//!   coordinates.

use crate::error::{Context, Result};
use junta_core::element::StepInfo;
use junta_core::Model;
use std::io::Write;
use std::path::Path;

fn write_array(path: &Path, rows: usize, cols: usize, col_major: &[f64]) -> Result<()> {
    let mut w = std::io::BufWriter::new(
        std::fs::File::create(path).with_context(|| format!("cannot write {}", path.display()))?,
    );
    writeln!(w, "%%MatrixMarket matrix array real general")?;
    writeln!(w, "% written by junta")?;
    writeln!(w, "{rows} {cols}")?;
    for v in col_major {
        writeln!(w, "{v:e}")?;
    }
    Ok(())
}

/// Write `K.mtx`, `b.mtx`, `B.mtx` and `layout.csv` of `model` into `dir`.
pub fn export_matrix(model: &Model, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create directory {}", dir.display()))?;
    let asm = model.whole_assembler();
    let mut k = asm.pattern.clone();
    let mut f_int = vec![0.0; model.dofs.num_dofs()];
    let mut state = model.initial_state();
    let u0 = model.dofs.expand(None, 1.0);
    asm.assemble(
        &model.mesh,
        &model.elements,
        &model.dofs,
        &u0,
        &mut state,
        StepInfo::default(),
        Some(&mut k),
        &mut f_int,
    )
    .context("assembling the stiffness for --export-matrix")?;
    let n = k.n;
    // sprs writes the entries with row <= column of a symmetric matrix
    let mut tri = sprs::TriMat::with_capacity((n, n), k.nnz());
    for j in 0..n {
        for p in k.col_ptr[j]..k.col_ptr[j + 1] {
            tri.add_triplet(k.row_idx[p], j, k.values[p]);
        }
    }
    let csc: sprs::CsMat<f64> = tri.to_csc();
    let kp = dir.join("K.mtx");
    sprs::io::write_matrix_market_sym(&kp, &csc, sprs::io::SymmetryMode::Symmetric)
        .with_context(|| format!("cannot write {}", kp.display()))?;
    let fe = model.dofs.reduce(&model.f_ext);
    let fi = model.dofs.reduce(&f_int);
    let b: Vec<f64> = fe.iter().zip(&fi).map(|(e, i)| e - i).collect();
    write_array(&dir.join("b.mtx"), n, 1, &b)?;
    let coords = model.dofs.equation_coords(&model.mesh.nodes);
    let layout = model.equation_layout();
    let modes = junta_solvers::amg::rigid_modes(&coords, &layout);
    let mut cm = Vec::with_capacity(6 * n);
    for c in 0..junta_solvers::amg::NULL_DIM {
        cm.extend(modes.iter().map(|r| r[c]));
    }
    write_array(&dir.join("B.mtx"), n, junta_solvers::amg::NULL_DIM, &cm)?;
    let lp = dir.join("layout.csv");
    let mut w = std::io::BufWriter::new(
        std::fs::File::create(&lp).with_context(|| format!("cannot write {}", lp.display()))?,
    );
    writeln!(w, "equation,node,component,body,x,y,z")?;
    for (i, x) in coords.iter().enumerate() {
        writeln!(
            w,
            "{i},{},{},{},{:e},{:e},{:e}",
            layout.node[i], layout.component[i], layout.body[i], x[0], x[1], x[2]
        )?;
    }
    Ok(())
}
