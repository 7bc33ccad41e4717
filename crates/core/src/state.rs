//! Integration-point state storage: one flat vector of committed values and
//! one of trial values. Each element of each block owns a fixed slice. The
//! driver copies trial -> committed on convergence ([`StateStore::commit`])
//! and committed -> trial on cut-back ([`StateStore::restore`]); a
//! checkpoint is a plain write of `committed`.

/// Committed and trial state of every element.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StateStore {
    /// Committed values (last converged increment).
    pub committed: Vec<f64>,
    /// Trial values (current iteration).
    pub trial: Vec<f64>,
    /// Offset of each block's first element in the flat vectors.
    pub block_offsets: Vec<usize>,
    /// State length per element, per block.
    pub per_element: Vec<usize>,
}

impl StateStore {
    /// Layout for blocks of `(num_elements, state_len_per_element)`.
    pub fn new(blocks: &[(usize, usize)]) -> Self {
        let mut block_offsets = Vec::with_capacity(blocks.len());
        let mut per_element = Vec::with_capacity(blocks.len());
        let mut total = 0;
        for &(n, len) in blocks {
            block_offsets.push(total);
            per_element.push(len);
            total += n * len;
        }
        StateStore {
            committed: vec![0.0; total],
            trial: vec![0.0; total],
            block_offsets,
            per_element,
        }
    }

    /// Range of element `e` of block `b` in the flat vectors.
    pub fn range(&self, b: usize, e: usize) -> std::ops::Range<usize> {
        let s = self.block_offsets[b] + e * self.per_element[b];
        s..s + self.per_element[b]
    }

    /// The committed values of block `b`'s `len` elements.
    pub fn block_committed(&self, b: usize, len: usize) -> &[f64] {
        let start = self.block_offsets[b];
        &self.committed[start..start + len * self.per_element[b]]
    }

    /// Accept the trial state.
    pub fn commit(&mut self) {
        self.committed.copy_from_slice(&self.trial);
    }

    /// Discard the trial state.
    pub fn restore(&mut self) {
        self.trial.copy_from_slice(&self.committed);
    }
}
