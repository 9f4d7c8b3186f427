//! Walks a file's records, and those inside its uncompressed chunks, checking that each fits
//! where it lies, before the `mcap` crate's reader sees them: its reader subtracts an inner
//! record's length from an uncompressed chunk's without checking it (a panic in a debug
//! build, found by the fuzz target).

use super::{InspectError, bounds};

/// Chunk record opcode.
const CHUNK: u8 = 0x06;
/// Footer record opcode: the last record.
const FOOTER: u8 = 0x02;
/// A chunk's fixed fields before its compression name: start and end time, uncompressed
/// size, CRC.
const CHUNK_FIXED_BYTES: usize = 28;

/// Checks the records in `bytes` (from the first record to the closing magic, exclusive).
pub fn check(bytes: &[u8]) -> Result<(), InspectError> {
    let mut rest = bytes;
    while let Some((opcode, body, after)) = split_record(rest)? {
        bounds::check(opcode, body)?;
        if opcode == CHUNK {
            check_chunk(body)?;
        }
        if opcode == FOOTER {
            break;
        }
        rest = after;
    }
    Ok(())
}

/// A record's opcode and body, and the bytes after it.
type SplitRecord<'a> = (u8, &'a [u8], &'a [u8]);

/// The first record of `bytes` (opcode, body) and what follows it; none at the end.
fn split_record(bytes: &[u8]) -> Result<Option<SplitRecord<'_>>, InspectError> {
    let Some((&opcode, rest)) = bytes.split_first() else {
        return Ok(None);
    };
    let overrun = || InspectError::Corrupt {
        reason: format!(
            "a record (opcode {opcode:#04x}) runs past the end of what holds it ({} bytes)",
            bytes.len()
        ),
    };
    let (length, rest) = rest.split_first_chunk::<8>().ok_or_else(overrun)?;
    let length = usize::try_from(u64::from_le_bytes(*length)).map_err(|_| overrun())?;
    if length > rest.len() {
        return Err(overrun());
    }
    let (body, after) = rest.split_at(length);
    Ok(Some((opcode, body, after)))
}

/// Checks the records inside an uncompressed chunk (`body` passed [`bounds::check`]); a
/// compressed chunk's are checked by the reader as it decompresses them.
fn check_chunk(body: &[u8]) -> Result<(), InspectError> {
    let Some((compression_length, rest)) = body
        .get(CHUNK_FIXED_BYTES..)
        .and_then(<[u8]>::split_first_chunk::<4>)
    else {
        return Ok(());
    };
    if u32::from_le_bytes(*compression_length) != 0 {
        return Ok(());
    }
    let Some((_records_length, mut records)) = rest.split_first_chunk::<8>() else {
        return Ok(());
    };
    while let Some((opcode, inner, after)) = split_record(records)? {
        bounds::check(opcode, inner)?;
        records = after;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(opcode: u8, body: &[u8]) -> Vec<u8> {
        let mut bytes = vec![opcode];
        bytes.extend((body.len() as u64).to_le_bytes());
        bytes.extend(body);
        bytes
    }

    fn uncompressed_chunk(records: &[u8]) -> Vec<u8> {
        let mut body = vec![0; CHUNK_FIXED_BYTES];
        body.extend(0_u32.to_le_bytes());
        body.extend((records.len() as u64).to_le_bytes());
        body.extend(records);
        record(CHUNK, &body)
    }

    #[test]
    fn a_record_inside_an_uncompressed_chunk_must_fit_in_it() {
        let message = record(0x05, &[0; 22]);
        check(&uncompressed_chunk(&message)).expect("fits");
        let mut overlong = message.clone();
        overlong[1..9].copy_from_slice(&1000_u64.to_le_bytes());
        let error = check(&uncompressed_chunk(&overlong)).expect_err("overruns its chunk");
        assert!(error.to_string().contains("opcode 0x05"), "{error}");
    }

    #[test]
    fn a_top_level_record_must_fit_in_the_file() {
        let mut file = record(0x0F, &[0; 4]);
        file.truncate(file.len() - 1);
        assert!(check(&file).is_err());
    }
}
