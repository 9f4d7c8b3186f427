//! The one place that serializes: files, snapshots, control and the copying benchmark baseline.
//!
//! bincode is pinned to 2.0.1 (3.0.0 is a deliberate compile error); keeping every call behind
//! this module makes a move to another format a one-file change. The hot path never comes here.

use serde::{Serialize, de::DeserializeOwned};

/// Why encoding or decoding failed.
#[derive(Debug, thiserror::Error)]
pub enum CodecError {
    /// The value could not be encoded.
    #[error("encoding failed: {0}")]
    Encode(#[from] bincode::error::EncodeError),
    /// The bytes are not a valid encoding of the requested type.
    #[error("decoding failed: {0}")]
    Decode(#[from] bincode::error::DecodeError),
    /// The bytes held a valid value followed by unread bytes.
    #[error("decoding left {0} trailing bytes")]
    TrailingBytes(usize),
}

fn codec_config() -> impl bincode::config::Config {
    // Little-endian fixed-width integers: predictable sizes, fast for large byte arrays.
    // The limit makes a corrupt length prefix an error instead of a huge allocation.
    bincode::config::standard()
        .with_little_endian()
        .with_fixed_int_encoding()
        .with_limit::<MAX_DECODE_BYTES>()
}

/// Largest message the codec will decode: larger than any image pair or map snapshot we send.
pub const MAX_DECODE_BYTES: usize = 64 << 20;

/// Appends the encoding of `value` to `buffer` (cleared first), reusing its allocation.
pub fn encode_into<T: Serialize>(value: &T, buffer: &mut Vec<u8>) -> Result<(), CodecError> {
    buffer.clear();
    bincode::serde::encode_into_std_write(value, buffer, codec_config())?;
    Ok(())
}

/// Decodes a whole `T` from `bytes`; trailing bytes are an error.
pub fn decode<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, CodecError> {
    let (value, read_len) = bincode::serde::decode_from_slice(bytes, codec_config())?;
    if read_len != bytes.len() {
        return Err(CodecError::TrailingBytes(bytes.len() - read_len));
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Serialize, serde::Deserialize, PartialEq, Debug)]
    struct Sample {
        frame_index: u64,
        payload: Vec<u8>,
    }

    #[test]
    fn round_trip_keeps_value() {
        let sample = Sample {
            frame_index: 42,
            payload: vec![1, 2, 3],
        };
        let mut buffer = Vec::new();
        encode_into(&sample, &mut buffer).expect("encode");
        assert_eq!(decode::<Sample>(&buffer).expect("decode"), sample);
    }

    #[test]
    fn truncated_and_padded_bytes_are_rejected() {
        let mut buffer = Vec::new();
        encode_into(
            &Sample {
                frame_index: 1,
                payload: vec![9; 16],
            },
            &mut buffer,
        )
        .expect("encode");
        assert!(decode::<Sample>(&buffer[..buffer.len() - 1]).is_err());
        buffer.push(0);
        assert!(matches!(
            decode::<Sample>(&buffer),
            Err(CodecError::TrailingBytes(1))
        ));
    }

    #[test]
    fn arbitrary_bytes_never_panic() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for len in 0..256 {
            let bytes: Vec<u8> = (0..len)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    state as u8
                })
                .collect();
            let _ = decode::<Sample>(&bytes);
        }
    }
}
