"""load_lcp / save_lcp: round trips and clear errors."""

from __future__ import annotations

import numpy as np
import pytest

from lcpsim.io import LcpFileError, load_lcp, save_lcp

M = np.array([[2.0, 1.0], [1.0, 2.0]])
Q = np.array([-1.0, -1.0])


@pytest.mark.parametrize("name", ["p.npz", "p.h5", "p.hdf5"])
def test_round_trip(tmp_path, name):
    path = save_lcp(tmp_path / name, M, Q, attrs={"seed": 3})
    M2, q2 = load_lcp(path)
    np.testing.assert_array_equal(M2, M)
    np.testing.assert_array_equal(q2, Q)
    assert M2.dtype == np.float64


def test_format_sniffed_without_suffix(tmp_path):
    save_lcp(tmp_path / "a.npz", M, Q)
    save_lcp(tmp_path / "b.h5", M, Q)
    (tmp_path / "a.npz").rename(tmp_path / "a.bin")
    (tmp_path / "b.h5").rename(tmp_path / "b.bin")
    for p in ("a.bin", "b.bin"):
        np.testing.assert_array_equal(load_lcp(tmp_path / p)[0], M)


def test_int_arrays_are_converted(tmp_path):
    np.savez(tmp_path / "i.npz", M=np.eye(2, dtype=np.int32), q=np.array([1, -1]))
    M2, q2 = load_lcp(tmp_path / "i.npz")
    assert M2.dtype == np.float64 and q2.dtype == np.float64


def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        load_lcp(tmp_path / "nope.npz")


def _h5(path, **datasets):
    import h5py

    with h5py.File(path, "w") as f:
        for k, v in datasets.items():
            f.create_dataset(k, data=v)


@pytest.mark.parametrize(
    "make, parts",
    [
        (lambda p: np.savez(p / "x.npz", M=M), ["x.npz", "'q'", "found: M"]),
        (lambda p: np.savez(p / "x.npz", A=M, b=Q), ["'M' or 'q'", "found: A, b"]),
        (lambda p: np.savez(p / "x.npz", M=np.ones((2, 3)), q=Q), ["M", "square", "(2, 3)"]),
        (lambda p: np.savez(p / "x.npz", M=M, q=np.ones(3)), ["q has length 3"]),
        (lambda p: np.savez(p / "x.npz", M=M, q=np.ones((2, 1))), ["q", "1-D", "(2, 1)"]),
        (lambda p: np.savez(p / "x.npz", M=np.zeros((0, 0)), q=np.zeros(0)), ["empty"]),
        (lambda p: np.savez(p / "x.npz", M=np.array([[np.nan, 0], [0, 1]]), q=Q), ["M[0, 0]", "nan"]),
        (lambda p: np.savez(p / "x.npz", M=M.astype(complex), q=Q), ["M", "real numbers"]),
        (lambda p: np.savez(p / "x.npz", M=np.array([["a", "b"], ["c", "d"]]), q=Q), ["M", "real numbers"]),
        (lambda p: (p / "x.npz").write_bytes(b"this is not a zip file"), ["x.npz", "not a readable .npz"]),
        (lambda p: (p / "x.npz").write_bytes(b"PK\x03\x04 truncated"), ["x.npz", "not a readable .npz"]),
        (lambda p: np.save(p / "x.npy", M) or (p / "x.npy").rename(p / "x.npz"), ["x.npz", ".npz"]),
        (lambda p: (p / "x.h5").write_bytes(b"garbage, not hdf5"), ["x.h5", "not a readable HDF5"]),
        (lambda p: _h5(p / "x.h5", M=M), ["x.h5", "'/q'", "found: /M"]),
        (lambda p: _h5(p / "x.h5", M=np.ones(4), q=Q), ["M", "square", "(4,)"]),
        (lambda p: (p / "x.txt").write_text("M = 1"), ["x.txt", "unknown LCP file format"]),
    ],
    ids=[
        "npz-no-q", "npz-no-arrays", "npz-not-square", "npz-length", "npz-q-2d", "npz-empty", "npz-nan",
        "npz-complex", "npz-strings", "npz-garbage", "npz-truncated", "npy-not-npz", "h5-garbage", "h5-no-q",
        "h5-M-1d", "unknown-format",
    ],
)
def test_malformed_files(tmp_path, make, parts):
    make(tmp_path)
    path = next(p for p in tmp_path.iterdir())
    with pytest.raises(LcpFileError) as info:
        load_lcp(path)
    assert isinstance(info.value, ValueError)
    for part in parts:
        assert part in str(info.value), (part, str(info.value))


def test_directory(tmp_path):
    with pytest.raises(LcpFileError, match="directory"):
        load_lcp(tmp_path)


def test_h5_group_instead_of_dataset(tmp_path):
    import h5py

    with h5py.File(tmp_path / "g.h5", "w") as f:
        f.create_group("M")
        f.create_dataset("q", data=Q)
    with pytest.raises(LcpFileError, match="group"):
        load_lcp(tmp_path / "g.h5")


def test_save_unknown_suffix(tmp_path):
    with pytest.raises(LcpFileError, match="suffix"):
        save_lcp(tmp_path / "x.mat", M, Q)


def test_an_npz_member_flagged_as_encrypted_is_a_file_error(tmp_path):
    """zipfile refuses an encrypted member with a RuntimeError; the reader names the file."""
    import zipfile

    path = tmp_path / "enc.npz"
    np.savez(path, M=np.eye(2), q=-np.ones(2))
    raw = bytearray(path.read_bytes())
    with zipfile.ZipFile(path) as zf:
        info = zf.getinfo("q.npy")
    # The general-purpose flag (bit 0: encrypted) of q.npy's local header and central directory entry.
    raw[info.header_offset + 6] |= 1
    entry = raw.index(b"PK\x01\x02")
    while raw[entry + 46 : entry + 51] != b"q.npy":
        lengths = [int.from_bytes(raw[entry + i : entry + i + 2], "little") for i in (28, 30, 32)]
        entry += 46 + sum(lengths)
    raw[entry + 8] |= 1
    path.write_bytes(bytes(raw))
    with pytest.raises(LcpFileError, match="enc.npz"):
        load_lcp(path)
