//! The rows of the PETSc matrix a rank owns, summed on that rank and handed
//! to PETSc in CSR form.
//!
//! Each rank computes the tangent of its own elements, in Junta's
//! upper-triangle storage over the global equations. An entry
//! `(i, j)` of it (and `(j, i)` off the diagonal) belongs to the rank that
//! owns PETSc row `r(i)`. Most do belong to this rank: the others lie on the
//! rows of the nodes this rank shares with a lower rank, a thin layer.
//!
//! **Set-up, once per pattern.** The `(row, column)` pairs of the entries
//! owned elsewhere are sent to their owners (one all-to-all exchange). Each
//! rank then forms the CSR pattern of its own rows, the union of its own
//! entries and those it received, columns sorted and merged, and records for
//! every entry the slot it adds to (`slot`, `received_slot`). PETSc copies
//! the pattern once (`MatCreateMPIAIJWithArrays`).
//!
//! **Per tangent.** The values are summed into the slots: first this rank's
//! entries in storage order, then the received values in rank order. The
//! order is fixed, so the same tangent gives the same matrix bit for bit.
//! PETSc takes the values in place (`MatUpdateMPIAIJWithArray`).
//!
//! Memory: 8 bytes per owned matrix entry for the values, 4 per entry of
//! this rank's part for its slot, and PETSc's matrix (12 bytes per entry).
//! PETSc's own COO assembly (`MatSetPreallocationCOO`), which this replaces,
//! kept about 60 bytes per entry on each of several ranks (measured on the
//! 680k-equation H8 cube: 790 MB per rank on 4 ranks).

use crate::ffi::PetscInt;
use junta_core::{SolverError, SymmetricCsc};

/// Slot bit marking an entry sent to another rank; the rest of the slot is
/// its place in the send buffer.
const REMOTE: u32 = 1 << 31;

/// A rank's owned rows ([module docs](self)).
#[derive(Debug, Default)]
pub(crate) struct OwnedRows {
    /// Where each entry of this rank's part goes, in [`for_each_entry`]
    /// order: a slot of `values`, or `REMOTE |` a place in `send`.
    slot: Vec<u32>,
    /// Values of the owned rows, CSR order.
    pub values: Vec<f64>,
    /// Values sent to the other ranks, in rank order.
    send: Vec<f64>,
    /// Entries sent to each rank.
    send_counts: Vec<usize>,
    /// Values received, in rank order.
    received: Vec<f64>,
    /// Entries received from each rank.
    received_counts: Vec<usize>,
    /// Slot of each received value.
    received_slot: Vec<u32>,
}

/// The CSR pattern of the owned rows, for PETSc's matrix creation.
pub(crate) struct Pattern {
    /// Row pointers (owned rows + 1).
    pub row_ptr: Vec<PetscInt>,
    /// Global column of each entry, sorted within each row.
    pub columns: Vec<PetscInt>,
}

/// Every entry of `m` in a fixed order: column by column, each stored
/// `(i, j)` then, off the diagonal, its transpose `(j, i)`, with its value
/// (the transpose's from `lower` for a nonsymmetric matrix).
fn for_each_entry(m: &SymmetricCsc, mut f: impl FnMut(usize, usize, f64)) {
    let lower = if m.is_general() { &m.lower } else { &m.values };
    for j in 0..m.n {
        for p in m.col_ptr[j]..m.col_ptr[j + 1] {
            let i = m.row_idx[p];
            f(i, j, m.values[p]);
            if i != j {
                f(j, i, lower[p]);
            }
        }
    }
}

/// How the equations map to PETSc rows: `row[eq]`, and the first row of
/// each rank (`start[r]..start[r + 1]` are rank r's).
pub(crate) struct RowMap<'a> {
    pub row: &'a [u32],
    pub start: &'a [usize],
    pub rank: usize,
}

impl RowMap<'_> {
    fn owner(&self, r: usize) -> usize {
        self.start.partition_point(|&s| s <= r) - 1
    }
}

impl OwnedRows {
    /// Set up the owned rows of `m` (collective: every rank calls it).
    pub fn new(m: &SymmetricCsc, map: &RowMap) -> Result<(OwnedRows, Pattern), SolverError> {
        let size = map.start.len() - 1;
        let (first, last) = (map.start[map.rank], map.start[map.rank + 1]);
        let mut own_count = vec![0usize; last - first];
        let mut send_counts = vec![0usize; size];
        let mut entries = 0;
        for_each_entry(m, |i, _, _| {
            entries += 1;
            let r = map.row[i] as usize;
            match map.owner(r) {
                o if o == map.rank => own_count[r - first] += 1,
                o => send_counts[o] += 1,
            }
        });
        // the pairs owned elsewhere, in rank order, and their places
        let mut offset = prefix(&send_counts);
        let total: usize = send_counts.iter().sum();
        let mut pairs = vec![0 as PetscInt; 2 * total];
        let mut slot = Vec::with_capacity(entries);
        for_each_entry(m, |i, j, _| {
            let (r, c) = (map.row[i] as usize, map.row[j]);
            let o = map.owner(r);
            if o == map.rank {
                slot.push(0);
                return;
            }
            let k = offset[o];
            offset[o] += 1;
            pairs[2 * k] = r as PetscInt;
            pairs[2 * k + 1] = c as PetscInt;
            slot.push(REMOTE | k as u32);
        });
        // every rank agrees before the exchange, so that none is left in it
        if any_rank(total >= REMOTE as usize) {
            return Err(SolverError::OutOfMemory {
                detail: format!(
                    "petsc: a rank holds 2^31 or more matrix entries that belong to other ranks (this rank: {total}); more ranks give each fewer"
                ),
            });
        }
        let pair_counts: Vec<usize> = send_counts.iter().map(|c| 2 * c).collect();
        let (received_pairs, received_pair_counts) =
            crate::collective::exchange(&pairs, &pair_counts);
        drop(pairs);
        let received_counts: Vec<usize> = received_pair_counts.iter().map(|c| c / 2).collect();
        let mut rows = OwnedRows {
            slot,
            send: vec![0.0; total],
            received: vec![0.0; received_counts.iter().sum()],
            send_counts,
            received_counts,
            ..OwnedRows::default()
        };
        let pattern = rows.merge(m, map, own_count, &received_pairs)?;
        rows.values = vec![0.0; pattern.columns.len()];
        Ok((rows, pattern))
    }

    /// The CSR pattern of the owned rows from this rank's entries and the
    /// `received` pairs, and every entry's slot in it.
    fn merge(
        &mut self,
        m: &SymmetricCsc,
        map: &RowMap,
        mut count: Vec<usize>,
        received: &[PetscInt],
    ) -> Result<Pattern, SolverError> {
        let first = map.start[map.rank];
        let own = self.slot.len();
        for k in 0..received.len() / 2 {
            count[received[2 * k] as usize - first] += 1;
        }
        // unmerged rows: each entry's column and source (this rank's entry
        // t, or own + k for the k-th received one)
        let raw_ptr = prefix(&count);
        let mut next = raw_ptr.clone();
        let raw_len = raw_ptr[count.len()];
        let mut raw: Vec<(PetscInt, u32)> = vec![(0, 0); raw_len];
        let mut t = 0u32;
        for_each_entry(m, |i, j, _| {
            let r = map.row[i] as usize;
            if map.owner(r) == map.rank {
                raw[next[r - first]] = (map.row[j] as PetscInt, t);
                next[r - first] += 1;
            }
            t += 1;
        });
        for k in 0..received.len() / 2 {
            let r = received[2 * k] as usize - first;
            raw[next[r]] = (received[2 * k + 1], (own + k) as u32);
            next[r] += 1;
        }
        self.received_slot = vec![0; received.len() / 2];
        let mut row_ptr = Vec::with_capacity(count.len() + 1);
        let mut columns = Vec::with_capacity(raw_len);
        row_ptr.push(0);
        let mut too_many = false;
        for r in 0..count.len() {
            let entries = &mut raw[raw_ptr[r]..raw_ptr[r + 1]];
            entries.sort_unstable();
            for (idx, &(c, src)) in entries.iter().enumerate() {
                if idx == 0 || entries[idx - 1].0 != c {
                    columns.push(c);
                }
                let s = (columns.len() - 1) as u32;
                match (src as usize).checked_sub(own) {
                    None => self.slot[src as usize] = s,
                    Some(k) => self.received_slot[k] = s,
                }
            }
            if columns.len() > PetscInt::MAX as usize {
                too_many = true;
                break;
            }
            row_ptr.push(columns.len() as PetscInt);
        }
        // agreed by every rank, as the set-up's next step is collective
        if any_rank(too_many) {
            return Err(SolverError::OutOfMemory {
                detail: "petsc: a rank's rows hold more than 2^31 - 1 entries (32-bit PetscInt of the Debian build); more ranks give each fewer".into(),
            });
        }
        Ok(Pattern { row_ptr, columns })
    }

    /// Sum the entries of `m` (same pattern as at set-up) into `values`
    /// (collective).
    pub fn assemble(&mut self, m: &SymmetricCsc) {
        self.values.iter_mut().for_each(|v| *v = 0.0);
        let mut t = 0;
        let (values, send, slot) = (&mut self.values, &mut self.send, &self.slot);
        for_each_entry(m, |_, _, v| {
            let s = slot[t];
            if s & REMOTE == 0 {
                values[s as usize] += v;
            } else {
                send[(s & !REMOTE) as usize] = v;
            }
            t += 1;
        });
        crate::collective::exchange_into(
            &self.send,
            &self.send_counts,
            &mut self.received,
            &self.received_counts,
        );
        for (&s, &v) in self.received_slot.iter().zip(&self.received) {
            self.values[s as usize] += v;
        }
    }
}

/// Exclusive prefix sums: `out[k] = counts[..k].sum()`, with the total last.
fn prefix(counts: &[usize]) -> Vec<usize> {
    let mut out = Vec::with_capacity(counts.len() + 1);
    out.push(0);
    for &c in counts {
        out.push(out.last().copied().unwrap_or(0) + c);
    }
    out
}

/// Whether `flag` holds on any rank (on one process: `flag`); collective.
fn any_rank(flag: bool) -> bool {
    junta_core::distributed::collective().map_or(flag, |c| c.any(flag))
}
