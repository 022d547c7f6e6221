//! Reads the `M`, `q` of an uncompressed `.npz` (numpy's `savez`: a stored
//! zip of little-endian float64 `.npy` arrays), as the repository's
//! reproducers in `tests/data/repros/` are.

use lcp::Lcp;

/// The LCP of `tests/data/repros/NAME` (path from the workspace root).
pub fn repro(name: &str) -> Lcp {
    let path = format!("{}/../../tests/data/repros/{name}", env!("CARGO_MANIFEST_DIR"));
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let (m, q) = (array(&bytes, "M.npy"), array(&bytes, "q.npy"));
    Lcp::new(m, q).unwrap()
}

fn le(b: &[u8], at: usize, len: usize) -> usize {
    (0..len).fold(0, |a, k| a | (b[at + k] as usize) << (8 * k))
}

/// The float64 data of member `name` (local file headers walked in order).
fn array(zip: &[u8], name: &str) -> Vec<f64> {
    let mut at = 0;
    while zip[at..at + 4] == [0x50, 0x4b, 3, 4] {
        assert_eq!(le(zip, at + 8, 2), 0, "compressed member: only numpy's savez layout is read");
        let (mut size, name_len, extra) = (le(zip, at + 18, 4), le(zip, at + 26, 2), le(zip, at + 28, 2));
        let data = at + 30 + name_len + extra;
        if size == 0xffff_ffff {
            // Zip64 (numpy writes it): the size is in the extra field with id 1.
            let mut e = at + 30 + name_len;
            while le(zip, e, 2) != 1 {
                e += 4 + le(zip, e + 2, 2);
            }
            size = le(zip, e + 4, 8);
        }
        if &zip[at + 30..at + 30 + name_len] == name.as_bytes() {
            return npy(&zip[data..data + size]);
        }
        at = data + size;
    }
    panic!("no member {name}")
}

fn npy(b: &[u8]) -> Vec<f64> {
    assert_eq!(&b[..6], b"\x93NUMPY");
    let (header_len, start) = if b[6] == 1 { (le(b, 8, 2), 10) } else { (le(b, 8, 4), 12) };
    let header = std::str::from_utf8(&b[start..start + header_len]).unwrap();
    assert!(header.contains("'<f8'") && header.contains("'fortran_order': False"), "{header}");
    b[start + header_len..].chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect()
}
