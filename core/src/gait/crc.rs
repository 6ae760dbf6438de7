//! The gait file's checksum.

/// CRC-32 of `bytes` as in zip, PNG and IEEE 802.3: reflected, polynomial `0xEDB88320`,
/// initial value and final XOR `0xFFFFFFFF` (`crc32(b"123456789") = 0xCBF43926`). Bitwise,
/// no table: it runs once per gait.
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc32_check_value() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(crc32(b""), 0);
    }
}
