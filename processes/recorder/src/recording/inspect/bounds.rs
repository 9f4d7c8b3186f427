//! Checks every length a record announces against the bytes it has, before the `mcap` crate
//! parses it: its parser reserves a string's or an array's announced length before reading
//! it, so four corrupt bytes would ask for 4 GiB (found by the fuzz target).

use super::InspectError;

/// One field of a record's layout.
#[derive(Clone, Copy)]
enum Field {
    /// A fixed number of bytes (integers).
    Fixed(usize),
    /// A u32 length, then that many bytes (a string, schema data, an array, a map).
    Prefixed32,
    /// A u32 byte length, then string key and value pairs.
    StringMap,
    /// A u32 byte length, then entries of this many bytes each (the parser reads whole
    /// entries until it has passed the length, so a partial one would shift what follows).
    Entries32(usize),
    /// A u64 length, then that many bytes (attachment data, chunk records).
    Prefixed64,
}

use Field::{Entries32, Fixed, Prefixed32, Prefixed64, StringMap};

/// The layout of each record kind with a length inside it (MCAP specification, opcodes 0x01
/// to 0x0F); a kind not listed has only fixed fields or its data as the rest of the record.
fn layout(opcode: u8) -> &'static [Field] {
    match opcode {
        // Header: profile, library.
        0x01 => &[Prefixed32, Prefixed32],
        // Schema: id, name, encoding, data.
        0x03 => &[Fixed(2), Prefixed32, Prefixed32, Prefixed32],
        // Channel: id, schema id, topic, message encoding, metadata.
        0x04 => &[Fixed(4), Prefixed32, Prefixed32, StringMap],
        // Chunk: start and end time, uncompressed size, CRC, compression, records.
        0x06 => &[Fixed(28), Prefixed32, Prefixed64],
        // Message index: channel id, (time, offset) pairs.
        0x07 => &[Fixed(2), Entries32(16)],
        // Chunk index: times, offset, length, message index offsets (channel id: offset),
        // their length, compression, sizes.
        0x08 => &[Fixed(32), Entries32(10), Fixed(8), Prefixed32, Fixed(16)],
        // Attachment: times, name, media type, data, CRC.
        0x09 => &[Fixed(16), Prefixed32, Prefixed32, Prefixed64, Fixed(4)],
        // Attachment index: offset, length, times, data size, name, media type.
        0x0A => &[Fixed(40), Prefixed32, Prefixed32],
        // Statistics: counts, times, messages per channel id.
        0x0B => &[Fixed(42), Entries32(10)],
        // Metadata: name, entries.
        0x0C => &[Prefixed32, StringMap],
        // Metadata index: offset, length, name.
        0x0D => &[Fixed(16), Prefixed32],
        _ => &[],
    }
}

/// Whether every length inside the record with `opcode` and body `data` fits in it.
pub fn check(opcode: u8, data: &[u8]) -> Result<(), InspectError> {
    let overrun = || InspectError::Corrupt {
        reason: format!(
            "a record (opcode {opcode:#04x}, {} bytes) announces a field that does not fit in it",
            data.len()
        ),
    };
    let mut rest = data;
    for field in layout(opcode) {
        rest = match field {
            Fixed(size) => rest.get(*size..),
            Prefixed32 => skip_prefixed::<4>(rest).map(|(_, after)| after),
            Prefixed64 => skip_prefixed::<8>(rest).map(|(_, after)| after),
            Entries32(size) => skip_prefixed::<4>(rest)
                .filter(|(entries, _)| entries.len().is_multiple_of(*size))
                .map(|(_, after)| after),
            StringMap => skip_prefixed::<4>(rest).and_then(|(mut entries, after)| {
                while !entries.is_empty() {
                    let (_, value) = skip_prefixed::<4>(entries)?;
                    let (_, next) = skip_prefixed::<4>(value)?;
                    entries = next;
                }
                Some(after)
            }),
        }
        .ok_or_else(overrun)?;
    }
    Ok(())
}

/// Splits `bytes` after a little-endian length of `N` bytes and that many bytes: the field,
/// and what follows it; none if they do not fit.
fn skip_prefixed<const N: usize>(bytes: &[u8]) -> Option<(&[u8], &[u8])> {
    let (length, rest) = bytes.split_first_chunk::<N>()?;
    let mut wide = [0_u8; 8];
    wide[..N].copy_from_slice(length);
    let length = usize::try_from(u64::from_le_bytes(wide)).ok()?;
    (length <= rest.len()).then(|| rest.split_at(length))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn string(text: &str) -> Vec<u8> {
        let mut bytes = (text.len() as u32).to_le_bytes().to_vec();
        bytes.extend_from_slice(text.as_bytes());
        bytes
    }

    #[test]
    fn a_header_whose_strings_fit_passes_and_an_overlong_one_is_corrupt() {
        let mut header = string("hopnav");
        header.extend(string("mcap"));
        check(0x01, &header).expect("fits");
        let mut bomb = u32::MAX.to_le_bytes().to_vec();
        bomb.extend_from_slice(b"hopnav");
        let error = check(0x01, &bomb).expect_err("4 GiB string in 10 bytes");
        assert!(error.to_string().contains("opcode 0x01"), "{error}");
    }

    #[test]
    fn an_index_map_must_hold_whole_entries() {
        let mut statistics = vec![0; 42];
        statistics.extend(10_u32.to_le_bytes());
        statistics.extend([0; 10]);
        check(0x0B, &statistics).expect("one whole entry");
        statistics[42..46].copy_from_slice(&9_u32.to_le_bytes());
        assert!(check(0x0B, &statistics).is_err());
    }

    #[test]
    fn every_entry_of_a_metadata_map_is_checked() {
        let mut entries = string("commit");
        entries.extend(string("abc"));
        let mut metadata = string("hopnav.build");
        metadata.extend((entries.len() as u32).to_le_bytes());
        metadata.extend(&entries);
        check(0x0C, &metadata).expect("fits");
        // The value's length overruns the map, though the map fits in the record.
        let last = metadata.len() - 7;
        metadata[last..last + 4].copy_from_slice(&1000_u32.to_le_bytes());
        assert!(check(0x0C, &metadata).is_err());
    }
}
