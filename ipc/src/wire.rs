//! The wire encoding of recordings: a message's bytes exactly as they lie in shared memory.
//!
//! Every message is `#[repr(C)]`, made of integers and floats only, without padding (each
//! message file asserts its size), so its bytes are a lossless encoding that needs no
//! serializer: a recording stores them, and a replay reads them back into the same type. A
//! slice sample is its header's bytes followed by its elements' bytes.
//!
//! A type's [`WireBytes::LAYOUT_VERSION`] names its layout in a recording's schema
//! (`hopnav.PoseEstimate.v2`): bump it whenever a field of the type (or of a type inside it)
//! is added, removed, moved or retyped, so an old recording is refused, not misread.
//!
//! ```
//! use hopnav_ipc::messages::PoseEstimate;
//! use hopnav_ipc::wire;
//!
//! let mut pose = PoseEstimate::default();
//! pose.stamp.frame_index = 7;
//! let bytes = wire::bytes_of(&pose);
//! assert_eq!(wire::read::<PoseEstimate>(bytes), Some(pose));
//! ```

use crate::messages::{
    AltimeterSample, BodyStates, CellUpdate, CloudHeader, Control, DriveCommand, FeaturePoint,
    FrameTick, Heartbeat, HopLaunch, ImageHeader, ImuSample, JumpRequest, MapHeader, PathHeader,
    PathPoint, PhysicsState, PoseEstimate,
};

/// The message encoding a recording names for these bytes.
pub const MESSAGE_ENCODING: &str = "hopnav/repr-c";

/// The encoding of the schema text [`schema_text`] and [`slice_schema_text`] write.
pub const SCHEMA_ENCODING: &str = "hopnav/layout";

// The recorded bytes are little-endian; a big-endian build would record another encoding.
const _: () = assert!(cfg!(target_endian = "little"));

/// Types whose bytes are their wire encoding: every bit pattern of `size_of::<Self>()` bytes
/// is a valid value, and there is no padding between or after their fields.
///
/// # Safety
/// Implement only for `#[repr(C)]` types made of integers and floats alone (directly or through
/// nested such types and arrays), without padding: no `bool`, `char`, enum, reference or
/// pointer field.
pub unsafe trait WireBytes: Copy + 'static {
    /// The type's name in schemas, e.g. `PoseEstimate`.
    const TYPE_NAME: &'static str;
    /// The version of the type's layout (see the module documentation).
    const LAYOUT_VERSION: u32;
}

macro_rules! wire_bytes {
    ($($type:ident = $version:literal),+ $(,)?) => {
        $(
            // SAFETY: every hopnav message is `#[repr(C)]` with only `u32`/`u64`/`f32`/`f64`
            // fields and arrays of them (enumerations travel as `u32` codes), and each message
            // file asserts that its size is the sum of its fields; so any bit pattern is a
            // valid value, without padding.
            unsafe impl WireBytes for $type {
                const TYPE_NAME: &'static str = stringify!($type);
                const LAYOUT_VERSION: u32 = $version;
            }
        )+

        /// Every message type's name and layout version, as schemas name them: a reader of
        /// a recording checks its schemas against these.
        pub const LAYOUT_VERSIONS: &[(&str, u32)] = &[$((stringify!($type), $version)),+];
    };
}

wire_bytes!(
    FrameTick = 1,
    Heartbeat = 1,
    BodyStates = 1,
    AltimeterSample = 1,
    ImuSample = 1,
    PoseEstimate = 2,
    DriveCommand = 1,
    JumpRequest = 1,
    HopLaunch = 1,
    PhysicsState = 1,
    Control = 1,
    ImageHeader = 1,
    CloudHeader = 1,
    MapHeader = 1,
    PathHeader = 1,
    FeaturePoint = 1,
    CellUpdate = 1,
    PathPoint = 1,
);

// SAFETY: a byte has no padding and every bit pattern is a valid `u8`.
unsafe impl WireBytes for u8 {
    const TYPE_NAME: &'static str = "u8";
    const LAYOUT_VERSION: u32 = 1;
}

/// The bytes of `value`.
pub fn bytes_of<T: WireBytes>(value: &T) -> &[u8] {
    slice_bytes(std::slice::from_ref(value))
}

/// The bytes of `values`, one element after the other.
pub fn slice_bytes<T: WireBytes>(values: &[T]) -> &[u8] {
    // SAFETY: `T: WireBytes` has no padding, so all `size_of_val(values)` bytes behind the
    // pointer are initialized; `u8` has alignment 1 and the borrow keeps `values` alive and
    // unmodified for the returned lifetime.
    unsafe { std::slice::from_raw_parts(values.as_ptr().cast::<u8>(), size_of_val(values)) }
}

/// The `T` whose bytes are exactly `bytes`; `None` if the length differs.
pub fn read<T: WireBytes>(bytes: &[u8]) -> Option<T> {
    match read_prefix::<T>(bytes) {
        Some((value, [])) => Some(value),
        _ => None,
    }
}

/// A `T` from the front of `bytes` and the bytes after it; `None` if `bytes` is too short.
pub fn read_prefix<T: WireBytes>(bytes: &[u8]) -> Option<(T, &[u8])> {
    if bytes.len() < size_of::<T>() {
        return None;
    }
    // SAFETY: at least `size_of::<T>()` bytes are readable, `read_unaligned` needs no
    // alignment, and `T: WireBytes` makes every bit pattern a valid `T`.
    let value = unsafe { bytes.as_ptr().cast::<T>().read_unaligned() };
    Some((value, &bytes[size_of::<T>()..]))
}

/// The elements whose bytes are exactly `bytes`; `None` if the length is not a multiple.
pub fn read_slice<T: WireBytes>(bytes: &[u8]) -> Option<Vec<T>> {
    let size = size_of::<T>();
    if size == 0 || !bytes.len().is_multiple_of(size) {
        return None;
    }
    bytes.chunks_exact(size).map(read::<T>).collect()
}

/// A slice sample read back: its header and its elements.
pub fn read_slice_sample<H: WireBytes, E: WireBytes>(bytes: &[u8]) -> Option<(H, Vec<E>)> {
    let (header, rest) = read_prefix::<H>(bytes)?;
    Some((header, read_slice::<E>(rest)?))
}

/// The schema name of a message type, e.g. `hopnav.PoseEstimate.v2`.
pub fn schema_name<T: WireBytes>() -> String {
    format!("hopnav.{}.v{}", T::TYPE_NAME, T::LAYOUT_VERSION)
}

/// The schema name of a slice sample, e.g. `hopnav.ImageHeader.v1+u8[]`.
pub fn slice_schema_name<H: WireBytes, E: WireBytes>() -> String {
    format!(
        "{}+{}[]",
        schema_name::<H>(),
        if E::TYPE_NAME == "u8" {
            "u8".to_owned()
        } else {
            schema_name::<E>()
        }
    )
}

/// A short description of a message type's encoding, the schema data of its channel.
pub fn schema_text<T: WireBytes>() -> String {
    format!(
        "{} layout v{}: {} bytes, #[repr(C)] little-endian, no padding (hopnav-ipc messages)",
        T::TYPE_NAME,
        T::LAYOUT_VERSION,
        size_of::<T>()
    )
}

/// A short description of a slice sample's encoding: its header, then its elements.
pub fn slice_schema_text<H: WireBytes, E: WireBytes>() -> String {
    format!(
        "{}; then the slice: {} elements of {} bytes each, as many as the rest holds",
        schema_text::<H>(),
        E::TYPE_NAME,
        size_of::<E>()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slice_samples_round_trip() {
        let mut header = CloudHeader::default();
        header.stamp.sequence = 3;
        header.point_count = 2;
        let points = [
            FeaturePoint {
                track_id: 5,
                ..FeaturePoint::default()
            },
            FeaturePoint {
                depth_sigma_m: 0.25,
                ..FeaturePoint::default()
            },
        ];
        let mut bytes = bytes_of(&header).to_vec();
        bytes.extend_from_slice(slice_bytes(&points));
        let (read_header, read_points) =
            read_slice_sample::<CloudHeader, FeaturePoint>(&bytes).expect("read back");
        assert_eq!(read_header, header);
        assert_eq!(read_points, points);
        assert!(
            read_slice_sample::<CloudHeader, FeaturePoint>(&bytes[..bytes.len() - 1]).is_none()
        );
        assert!(read::<CloudHeader>(&bytes).is_none());
    }

    #[test]
    fn schema_names_carry_type_and_layout_version() {
        assert_eq!(schema_name::<PoseEstimate>(), "hopnav.PoseEstimate.v2");
        assert_eq!(
            slice_schema_name::<ImageHeader, u8>(),
            "hopnav.ImageHeader.v1+u8[]"
        );
        assert!(schema_text::<ImageHeader>().contains("160 bytes"));
    }
}
