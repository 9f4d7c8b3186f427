//! The probe image content: a pattern every byte of which depends on the frame, so a torn,
//! stale or swapped buffer is detected by checking all of it.

/// The value of byte `index` of the probe image of frame `frame_index`.
#[inline]
pub fn pattern_byte(frame_index: u64, index: usize) -> u8 {
    let mixed = (index as u64)
        .wrapping_mul(0x9E37_79B1)
        .wrapping_add(frame_index.wrapping_mul(0x85EB_CA77));
    (mixed ^ (mixed >> 13)) as u8
}

/// Index of the first byte that differs from the pattern of `frame_index`, if any.
pub fn first_mismatch(frame_index: u64, bytes: &[u8]) -> Option<usize> {
    bytes
        .iter()
        .enumerate()
        .position(|(index, byte)| *byte != pattern_byte(frame_index, index))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_detects_a_single_flipped_byte_and_a_stale_frame() {
        let frame = 17;
        let mut bytes: Vec<u8> = (0..4096).map(|index| pattern_byte(frame, index)).collect();
        assert_eq!(first_mismatch(frame, &bytes), None);
        assert!(first_mismatch(frame + 1, &bytes).is_some());
        bytes[1234] ^= 1;
        assert_eq!(first_mismatch(frame, &bytes), Some(1234));
    }
}
