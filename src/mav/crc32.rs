//! The CRC-32 of PX4's parameter hash and MAVLink FTP (the reflected 0xEDB88320 polynomial,
//! table-driven), without the usual initial and final inversion: `crc32_part` continues from a
//! state, as PX4's `crc32part` and QGroundControl's `QGC::crc32` do. Pure.

/// The byte table of the reflected polynomial 0xEDB88320.
const TABLE: [u32; 256] = table();

const fn table() -> [u32; 256] {
    let mut table = [0u32; 256];
    let mut n = 0;
    while n < 256 {
        let mut c = n as u32;
        let mut k = 0;
        while k < 8 {
            c = if c & 1 == 1 { 0xEDB8_8320 ^ (c >> 1) } else { c >> 1 };
            k += 1;
        }
        table[n] = c;
        n += 1;
    }
    table
}

/// `state` continued over `data`.
pub fn crc32_part(data: &[u8], state: u32) -> u32 {
    data.iter().fold(state, |crc, b| {
        TABLE[((crc ^ u32::from(*b)) & 0xFF) as usize] ^ (crc >> 8)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_standard_crc32_once_inverted_around() {
        // The standard CRC-32 of "123456789" is 0xCBF43926: inversion before and after.
        assert_eq!(!crc32_part(b"123456789", !0), 0xCBF4_3926);
        assert_eq!(crc32_part(b"", 7), 7);
        let whole = crc32_part(b"hello world", 0);
        assert_eq!(crc32_part(b" world", crc32_part(b"hello", 0)), whole);
    }
}
