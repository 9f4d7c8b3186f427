//! Borrowed 8-bit grayscale image view (no copy).
//!
//! An [`ImageView`] is a header (width, height, stride) over a byte slice it does not own, so it
//! can wrap an iceoryx2 sample payload in place.
//!
//! ```
//! use hopnav_vision::image::ImageView;
//! let pixels = vec![7u8; 4 * 3];
//! let view = ImageView::new(&pixels, 3, 3, 4).unwrap(); // one padding byte per row
//! assert_eq!(view.get(2, 2), Some(7));
//! assert_eq!(view.row(1).map(<[u8]>::len), Some(3));
//! ```

/// Error wrapping a byte slice as an [`ImageView`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ImageViewError {
    /// Width or height is zero.
    #[error("image size must be non-zero, got {width}x{height}")]
    ZeroSize {
        /// Requested width in pixels.
        width: usize,
        /// Requested height in pixels.
        height: usize,
    },
    /// The row stride is shorter than a row.
    #[error("stride {stride} is smaller than width {width}")]
    StrideTooSmall {
        /// Requested stride in bytes.
        stride: usize,
        /// Requested width in pixels.
        width: usize,
    },
    /// The slice cannot hold `stride * (height - 1) + width` bytes.
    #[error("buffer holds {len} bytes, image needs {required}")]
    BufferTooSmall {
        /// Slice length.
        len: usize,
        /// Bytes the header requires.
        required: usize,
    },
}

/// Read-only 8-bit grayscale image borrowed from a byte slice.
#[derive(Debug, Clone, Copy)]
pub struct ImageView<'a> {
    data: &'a [u8],
    width: usize,
    height: usize,
    stride: usize,
}

impl<'a> ImageView<'a> {
    /// Wraps `data` with the given header after checking it fits.
    pub fn new(
        data: &'a [u8],
        width: usize,
        height: usize,
        stride: usize,
    ) -> Result<Self, ImageViewError> {
        if width == 0 || height == 0 {
            return Err(ImageViewError::ZeroSize { width, height });
        }
        if stride < width {
            return Err(ImageViewError::StrideTooSmall { stride, width });
        }
        let required = stride
            .checked_mul(height - 1)
            .and_then(|v| v.checked_add(width))
            .ok_or(ImageViewError::BufferTooSmall {
                len: data.len(),
                required: usize::MAX,
            })?;
        if data.len() < required {
            return Err(ImageViewError::BufferTooSmall {
                len: data.len(),
                required,
            });
        }
        Ok(Self {
            data,
            width,
            height,
            stride,
        })
    }

    /// Wraps a tightly packed buffer (`stride == width`).
    pub fn packed(data: &'a [u8], width: usize, height: usize) -> Result<Self, ImageViewError> {
        Self::new(data, width, height, width)
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Row stride in bytes.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Row `y` (exactly `width` bytes), `None` out of range.
    pub fn row(&self, y: usize) -> Option<&'a [u8]> {
        if y >= self.height {
            return None;
        }
        let start = y * self.stride;
        self.data.get(start..start + self.width)
    }

    /// Pixel `(x, y)`, `None` out of range.
    pub fn get(&self, x: usize, y: usize) -> Option<u8> {
        if x >= self.width {
            return None;
        }
        self.row(y).and_then(|r| r.get(x).copied())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validates_header() {
        let buf = [0u8; 10];
        assert!(matches!(
            ImageView::new(&buf, 0, 1, 1),
            Err(ImageViewError::ZeroSize { .. })
        ));
        assert!(matches!(
            ImageView::new(&buf, 4, 2, 3),
            Err(ImageViewError::StrideTooSmall { .. })
        ));
        assert!(matches!(
            ImageView::new(&buf, 4, 3, 4),
            Err(ImageViewError::BufferTooSmall { required: 12, .. })
        ));
        // The last row needs no padding.
        assert!(ImageView::new(&buf, 4, 2, 6).is_ok());
        assert!(ImageView::new(&buf, 1, 2, usize::MAX).is_err());
    }

    #[test]
    fn strided_access() {
        let buf: Vec<u8> = (0..20).collect();
        let v = ImageView::new(&buf, 3, 4, 5).unwrap();
        assert_eq!(v.get(2, 3), Some(17));
        assert_eq!(v.get(3, 0), None);
        assert_eq!(v.row(4), None);
        assert_eq!(v.row(1), Some(&buf[5..8]));
    }
}
