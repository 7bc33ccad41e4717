//! [`junta_core::distributed::Collective`] on MPI (`PETSC_COMM_WORLD`).
//! A failed MPI call ends every rank (`MPI_Abort`): a collective that
//! failed on one rank would leave the others waiting.

use crate::ffi;
use junta_core::distributed::Collective;

/// The ranks of `PETSC_COMM_WORLD`.
#[derive(Debug)]
pub struct MpiCollective {
    rank: usize,
    size: usize,
}

impl MpiCollective {
    /// The world communicator's rank and size (PETSc initialised).
    pub(crate) fn world() -> Self {
        // SAFETY: plain queries after PetscInitialize.
        let (rank, size) = unsafe { (ffi::junta_rank(), ffi::junta_size()) };
        MpiCollective {
            rank: rank.max(0) as usize,
            size: size.max(1) as usize,
        }
    }
}

/// End every rank when an MPI call failed.
fn check(code: i32, what: &str) {
    if code != 0 {
        crate::abort_all(&format!("MPI {what} failed: {}", ffi::error_text(code)));
    }
}

impl Collective for MpiCollective {
    fn rank(&self) -> usize {
        self.rank
    }
    fn size(&self) -> usize {
        self.size
    }
    fn sum_in_place(&self, v: &mut [f64]) {
        // SAFETY: v is valid for v.len() doubles.
        check(
            unsafe { ffi::junta_sum(v.as_mut_ptr(), v.len() as i64) },
            "sum",
        );
    }
    fn max_in_place(&self, v: &mut [f64]) {
        // SAFETY: as above.
        check(
            unsafe { ffi::junta_max(v.as_mut_ptr(), v.len() as i64) },
            "max",
        );
    }
    fn min_in_place_usize(&self, v: &mut [usize]) {
        let mut w: Vec<u64> = v.iter().map(|&x| x as u64).collect();
        // SAFETY: w is valid for w.len() integers.
        check(
            unsafe { ffi::junta_min_u64(w.as_mut_ptr(), w.len() as i64) },
            "min",
        );
        for (a, b) in v.iter_mut().zip(w) {
            *a = b as usize;
        }
    }
    fn any(&self, flag: bool) -> bool {
        let mut any = 0;
        // SAFETY: any is a valid int.
        check(
            unsafe { ffi::junta_any(flag as i32, &mut any) },
            "flag reduction",
        );
        any != 0
    }
    fn broadcast_bytes(&self, root: usize, bytes: &mut Vec<u8>) {
        let mut len = [bytes.len() as f64];
        // the length first (exact in a double up to 2^53)
        // SAFETY: valid buffers of the stated sizes.
        check(
            unsafe { ffi::junta_bcast(len.as_mut_ptr().cast(), 8, root as i32) },
            "broadcast",
        );
        bytes.resize(len[0] as usize, 0);
        check(
            unsafe { ffi::junta_bcast(bytes.as_mut_ptr().cast(), bytes.len() as i64, root as i32) },
            "broadcast",
        );
    }
}

/// Send `counts[r]` items of `send` (in rank order) to each rank r and
/// receive what every rank sends here: the items in rank order and their
/// counts per rank. Collective.
pub(crate) fn exchange<T: Copy + Default>(send: &[T], counts: &[usize]) -> (Vec<T>, Vec<usize>) {
    let send_counts: Vec<i64> = counts.iter().map(|&c| c as i64).collect();
    let mut received_counts = vec![0i64; counts.len()];
    // SAFETY: both arrays hold one count per rank.
    check(
        unsafe { ffi::junta_alltoall_counts(send_counts.as_ptr(), received_counts.as_mut_ptr()) },
        "count exchange",
    );
    let received_counts: Vec<usize> = received_counts.iter().map(|&c| c as usize).collect();
    let mut received = vec![T::default(); received_counts.iter().sum()];
    exchange_into(send, counts, &mut received, &received_counts);
    (received, received_counts)
}

/// [`exchange`] with the receiving counts known and the buffer given.
pub(crate) fn exchange_into<T: Copy>(
    send: &[T],
    send_counts: &[usize],
    received: &mut [T],
    received_counts: &[usize],
) {
    let item = std::mem::size_of::<T>();
    let bytes =
        |counts: &[usize]| -> Vec<i64> { counts.iter().map(|&c| (c * item) as i64).collect() };
    let (sb, rb) = (bytes(send_counts), bytes(received_counts));
    let limit = i32::MAX as i64;
    if sb.iter().sum::<i64>() > limit || rb.iter().sum::<i64>() > limit {
        crate::abort_all("an exchange between ranks passes 2 GB (MPI's int counts)");
    }
    assert_eq!(send.len(), send_counts.iter().sum::<usize>(), "send counts");
    assert_eq!(
        received.len(),
        received_counts.iter().sum::<usize>(),
        "receive counts"
    );
    // SAFETY: the buffers hold the stated bytes; T is plain data.
    check(
        unsafe {
            ffi::junta_alltoallv_bytes(
                send.as_ptr().cast(),
                sb.as_ptr(),
                received.as_mut_ptr().cast(),
                rb.as_ptr(),
            )
        },
        "exchange",
    );
}
