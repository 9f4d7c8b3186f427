//! Binary 8-bit PGM (P5): the simplest lossless grey image any tool reads.

use std::io::{self, BufRead, Write};

/// Why a PGM could not be read.
#[derive(Debug, thiserror::Error)]
pub enum PgmError {
    /// Reading failed.
    #[error("PGM read failed: {0}")]
    Io(#[from] io::Error),
    /// Not a binary 8-bit PGM, or a malformed header.
    #[error("not an 8-bit binary PGM: {0}")]
    Format(String),
}

/// Writes `pixels` (rows of `width_px` bytes, `stride_bytes` apart) as a P5 PGM.
pub fn write_pgm(
    out: &mut impl Write,
    width_px: usize,
    height_px: usize,
    stride_bytes: usize,
    pixels: &[u8],
) -> io::Result<()> {
    if stride_bytes < width_px
        || pixels.len() < stride_bytes * height_px.saturating_sub(1) + width_px
    {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "{} bytes cannot hold {width_px}x{height_px} with stride {stride_bytes}",
                pixels.len()
            ),
        ));
    }
    write!(out, "P5\n{width_px} {height_px}\n255\n")?;
    for row in 0..height_px {
        let start = row * stride_bytes;
        out.write_all(&pixels[start..start + width_px])?;
    }
    Ok(())
}

/// A decoded grey image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GreyImage {
    /// Width, pixels.
    pub width_px: usize,
    /// Height, pixels.
    pub height_px: usize,
    /// Row-major pixels, no padding.
    pub pixels: Vec<u8>,
}

fn header_token(input: &mut impl BufRead) -> Result<String, PgmError> {
    let mut token = String::new();
    loop {
        let mut byte = [0_u8; 1];
        if input.read(&mut byte)? == 0 {
            return if token.is_empty() {
                Err(PgmError::Format("header ends early".into()))
            } else {
                Ok(token)
            };
        }
        match byte[0] {
            b'#' if token.is_empty() => {
                let mut comment = Vec::new();
                input.read_until(b'\n', &mut comment)?;
            }
            b' ' | b'\t' | b'\n' | b'\r' if token.is_empty() => {}
            b' ' | b'\t' | b'\n' | b'\r' => return Ok(token),
            other if token.len() < 16 => token.push(other as char),
            _ => return Err(PgmError::Format("header token too long".into())),
        }
    }
}

/// Reads a P5 PGM with maxval 255.
pub fn read_pgm(input: &mut impl BufRead) -> Result<GreyImage, PgmError> {
    if header_token(input)? != "P5" {
        return Err(PgmError::Format("magic is not P5".into()));
    }
    let mut number = |what: &str| -> Result<usize, PgmError> {
        header_token(input)?
            .parse::<usize>()
            .map_err(|_| PgmError::Format(format!("{what} is not a number")))
    };
    let width_px = number("width")?;
    let height_px = number("height")?;
    let max_value = number("maxval")?;
    if max_value != 255 || width_px == 0 || height_px == 0 || width_px * height_px > (1 << 28) {
        return Err(PgmError::Format(format!(
            "unsupported {width_px}x{height_px}, maxval {max_value}"
        )));
    }
    let mut pixels = vec![0; width_px * height_px];
    input
        .read_exact(&mut pixels)
        .map_err(|_| PgmError::Format("pixel data shorter than the header says".into()))?;
    Ok(GreyImage {
        width_px,
        height_px,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_with_stride() {
        let pixels: Vec<u8> = (0..4 * 3).map(|i| i as u8).collect(); // stride 4, width 3
        let mut bytes = Vec::new();
        write_pgm(&mut bytes, 3, 3, 4, &pixels).expect("write");
        let image = read_pgm(&mut bytes.as_slice()).expect("read");
        assert_eq!(image.width_px, 3);
        assert_eq!(image.pixels, vec![0, 1, 2, 4, 5, 6, 8, 9, 10]);
    }

    #[test]
    fn malformed_files_are_errors_not_panics() {
        for bad in [
            &b""[..],
            b"P6\n1 1\n255\n\0",
            b"P5\n2 2\n255\n\0",
            b"P5\n# c\nx 1\n255\n",
            b"P5 99999999 99999999 255 ",
        ] {
            assert!(read_pgm(&mut &bad[..]).is_err());
        }
        assert!(write_pgm(&mut Vec::new(), 4, 4, 4, &[0; 15]).is_err());
    }
}
