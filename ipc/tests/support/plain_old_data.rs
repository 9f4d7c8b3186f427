//! Messages made from raw bytes, as a crashed or faulty producer may leave them in shared
//! memory. Shared by `ipc/tests/corrupt_samples.rs` and the `sample_validate` fuzz target
//! (through `#[path]`), so one safety argument covers both.

use std::mem::{MaybeUninit, size_of};

use hopnav_ipc::messages::{
    AltimeterSample, BodyStates, CellUpdate, CloudHeader, Control, DriveCommand, FeaturePoint,
    FrameTick, Heartbeat, HopLaunch, ImageHeader, ImuSample, JumpRequest, MapHeader, PathHeader,
    PathPoint, PhysicsState, PoseEstimate,
};

/// Types whose every bit pattern of `size_of::<Self>()` bytes is a valid value, with no
/// padding between or after their fields.
///
/// # Safety
/// Implement only for `#[repr(C)]` types made of integers and floats alone (directly or through
/// nested such types and arrays), without padding: no `bool`, `char`, enum, reference or
/// pointer field.
pub unsafe trait PlainOldData: Copy {}

macro_rules! plain_old_data {
    ($($type:ty),+ $(,)?) => {
        $(
            // SAFETY: every hopnav message is `#[repr(C)]` with only `u32`/`u64`/`f32`/`f64`
            // fields and arrays of them (enumerations travel as `u32` codes), and each message
            // file asserts that its size is the sum of its fields, see
            // `ipc/src/messages/mod.rs`; so any bit pattern is a valid value, without padding.
            unsafe impl PlainOldData for $type {}
        )+
    };
}

plain_old_data!(
    FrameTick,
    Heartbeat,
    BodyStates,
    AltimeterSample,
    ImuSample,
    PoseEstimate,
    DriveCommand,
    JumpRequest,
    HopLaunch,
    PhysicsState,
    Control,
    ImageHeader,
    CloudHeader,
    MapHeader,
    PathHeader,
    FeaturePoint,
    CellUpdate,
    PathPoint,
);

/// A `T` from the front of `bytes` (zero-padded if short) and the bytes after it.
pub fn take<T: PlainOldData>(bytes: &[u8]) -> (T, &[u8]) {
    let mut value = MaybeUninit::<T>::zeroed();
    let len = bytes.len().min(size_of::<T>());
    // SAFETY: `value` is `size_of::<T>()` writable bytes and `len` does not exceed that; the
    // source is a distinct slice of at least `len` bytes, so the ranges do not overlap.
    unsafe {
        std::ptr::copy_nonoverlapping(bytes.as_ptr(), value.as_mut_ptr().cast::<u8>(), len);
    }
    // SAFETY: all `size_of::<T>()` bytes are initialized (zeroed, then partly overwritten) and
    // `T: PlainOldData` promises that every bit pattern is a valid `T`.
    (unsafe { value.assume_init() }, &bytes[len..])
}
