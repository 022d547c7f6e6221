//! Reads a `.lcpsparse` reproducer: an LCP too large for a dense `.npz` in
//! the repository, with the warm basis it was solved from. Layout (little
//! endian): `b"LCPSPARSE1"`, `n: u64`, `nnz: u64`, `nnz` flat indices
//! `i·n + j: u32` of the nonzero `M_ij` (ascending), their `nnz` values
//! `f64`, `q` (`n` × `f64`), the basis (`n` bytes, 1 = `z_j` basic).

use lcp::Lcp;

/// The LCP and warm basis of `tests/data/repros/NAME`.
pub fn repro_sparse(name: &str) -> (Lcp, Vec<bool>) {
    let path = format!("{}/../../tests/data/repros/{name}", env!("CARGO_MANIFEST_DIR"));
    let b = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    assert_eq!(&b[..10], b"LCPSPARSE1", "{path}: not an .lcpsparse file");
    let u64_at = |at: usize| u64::from_le_bytes(b[at..at + 8].try_into().unwrap()) as usize;
    let f64_at = |at: usize| f64::from_le_bytes(b[at..at + 8].try_into().unwrap());
    let (n, nnz) = (u64_at(10), u64_at(18));
    let (idx, vals) = (26, 26 + 4 * nnz);
    let mut m = vec![0.0; n * n];
    for k in 0..nnz {
        let i = u32::from_le_bytes(b[idx + 4 * k..idx + 4 * k + 4].try_into().unwrap()) as usize;
        m[i] = f64_at(vals + 8 * k);
    }
    let qs = vals + 8 * nnz;
    let q = (0..n).map(|i| f64_at(qs + 8 * i)).collect();
    let basis = b[qs + 8 * n..qs + 9 * n].iter().map(|&v| v != 0).collect();
    (Lcp::new(m, q).unwrap(), basis)
}
