//! CRC-16/MODBUS, the one implementation of the toolchain (the `crc` crate): the
//! manifest's page checksums and the Modbus RTU frames of gutta-protocol both call it.

const CRC16_MODBUS: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_MODBUS);

/// CRC-16/MODBUS (poly 0x8005 reflected, init 0xFFFF) of `bytes`. On a Modbus RTU line it
/// goes low byte first; in manifest.json it is written as `0x` and four hex digits.
pub fn crc16(bytes: &[u8]) -> u16 {
    CRC16_MODBUS.checksum(bytes)
}

#[cfg(test)]
mod tests {
    use super::crc16;

    #[test]
    fn check_value_and_an2002_frame() {
        // The catalogue check value of CRC-16/MODBUS.
        assert_eq!(crc16(b"123456789"), 0x4B37);
        // AN2002: 01 02 00 04 00 04 goes out with CRC bytes 38 08.
        assert_eq!(crc16(&[0x01, 0x02, 0x00, 0x04, 0x00, 0x04]), 0x0838);
    }
}
