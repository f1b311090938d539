//! FNV-1a 64-bit hashes: the one fingerprint of configurations (real-time states, sweeps) and the
//! checksum of serialised states. Not cryptographic: it detects a mismatch or a damaged byte,
//! not an attack.

/// The FNV-1a 64-bit offset basis: the hash of no bytes, where [`fnv1a64_continue`] starts.
pub const FNV1A64_START: u64 = 0xcbf2_9ce4_8422_2325;

/// The FNV-1a 64-bit hash of `data`.
pub fn fnv1a64(data: &[u8]) -> u64 {
    fnv1a64_continue(FNV1A64_START, data)
}

/// [`fnv1a64`] continued over `data` from the hash `h` of what came before (a file hashed in
/// chunks gives the hash of the whole).
pub fn fnv1a64_continue(mut h: u64, data: &[u8]) -> u64 {
    for &b in data {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// [`fnv1a64`] as 16 hexadecimal digits (sweep manifests).
pub fn fnv1a64_hex(data: &[u8]) -> String {
    format!("{:016x}", fnv1a64(data))
}
