//! Feature tracks of the front end (paper steps 1–2): KLT from frame to frame, each track
//! remembering its position in the current keyframe, so the geometry can be estimated over the
//! extended keyframe baseline (§2.1).
//!
//! The initial KLT guess of a track is its last displacement (constant image velocity), which
//! keeps the pyramid search small under the large flow of a 10 fps hop. New corners are only
//! added when a keyframe is set, so every live track has a keyframe position, and each track
//! also remembers where it was born: the keyframe ([`FeatureTracks::keyframe_serial`]) and
//! position where its corner was detected, so a cloud can triangulate it over all the
//! parallax it has gathered since, not only over the last keyframe interval.

use hopnav_vision::corners::{Corner, CornerConfig, CornerDetector, CornerError};
use hopnav_vision::image::ImageView;
use hopnav_vision::klt::{KltConfig, KltError, KltTracker, TrackStatus};
use hopnav_vision::pyramid::{Pyramid, PyramidConfig, PyramidError};
use nalgebra::{Point2, Vector2};

/// Error of the front end.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrackError {
    /// Pyramid construction or image size.
    #[error("pyramid: {0}")]
    Pyramid(#[from] PyramidError),
    /// KLT configuration or call.
    #[error("klt: {0}")]
    Klt(#[from] KltError),
    /// Corner detector configuration or call.
    #[error("corners: {0}")]
    Corners(#[from] CornerError),
}

/// Pyramid levels searched for a track with a measured displacement: the constant-velocity
/// guess is within a few pixels, so levels 1 and 0 suffice (new corners search all 4).
const TRACKED_LEVELS: u8 = 2;

/// Tracks, pyramids and detector of one camera.
#[derive(Debug, Clone)]
pub struct FeatureTracks {
    pyr_prev: Pyramid,
    pyr_cur: Pyramid,
    has_prev: bool,
    klt: KltTracker,
    detector: CornerDetector,
    max_features: usize,
    /// Positions in the last frame.
    cur_px: Vec<Point2<f32>>,
    /// Positions in the keyframe.
    kf_px: Vec<Point2<f32>>,
    /// Positions in the keyframe the track was born in.
    birth_px: Vec<Point2<f32>>,
    /// Serial of the keyframe the track was born in.
    birth_serial: Vec<u32>,
    /// Identity of each track, unique over the tracker's life (the bundle adjustment joins a
    /// track's sightings across keyframes by it).
    track_id: Vec<u32>,
    /// The identity the next new track gets.
    next_track_id: u32,
    /// Serial of the current keyframe (counts every [`Self::set_keyframe`]).
    keyframe_serial: u32,
    /// Last image displacement (prediction for the next frame).
    flow_px: Vec<Vector2<f32>>,
    /// Pyramid levels KLT searches per track: all for new corners (median-flow guess), fewer
    /// once a track has a measured displacement (constant-velocity guess).
    levels: Vec<u8>,
    /// Levels for tracks with a measured displacement.
    tracked_levels: u8,
    next_px: Vec<Point2<f32>>,
    status: Vec<TrackStatus>,
    corners: Vec<Corner>,
    keyframe_count: usize,
    /// Scratch of [`median_flow`] (per-axis flow components).
    flow_scratch: [Vec<f32>; 2],
}

impl FeatureTracks {
    /// Allocates everything for `width × height` frames and up to `max_features` tracks.
    pub fn new(width: usize, height: usize, max_features: usize) -> Result<Self, TrackError> {
        let pyr = PyramidConfig {
            levels: 4,
            border_px: 12,
        };
        // Measured on `hopnav eval vo --seeds 5` / `bench vo`: an 11 px window, 10 iterations
        // to 0.03 px, and 2 levels for tracks with a constant-velocity guess cost less than
        // half of a 15 px window over 4 levels to 0.01 px, at the same ATE. Coarse levels only
        // seed the next one: stopping them at 0.15 px (not 0.05) saves ~8 % of the frame with
        // no change beyond seed-to-seed noise (eval vo --seeds 5 and five recorded launches).
        let klt = KltConfig {
            window_radius_px: 5,
            epsilon_px: 0.03,
            coarse_epsilon_px: 0.15,
            max_iterations: 10,
            ..KltConfig::default()
        };
        let corners = CornerConfig {
            max_features,
            min_distance_px: 7.0,
            fill_leftover_budget: true,
            ..CornerConfig::default()
        };
        Ok(Self {
            pyr_prev: Pyramid::new(width, height, pyr)?,
            pyr_cur: Pyramid::new(width, height, pyr)?,
            has_prev: false,
            klt: KltTracker::new(klt, max_features)?,
            detector: CornerDetector::new(width, height, corners)?,
            max_features,
            cur_px: Vec::with_capacity(max_features),
            kf_px: Vec::with_capacity(max_features),
            birth_px: Vec::with_capacity(max_features),
            birth_serial: Vec::with_capacity(max_features),
            track_id: Vec::with_capacity(max_features),
            next_track_id: 0,
            keyframe_serial: 0,
            flow_px: Vec::with_capacity(max_features),
            levels: Vec::with_capacity(max_features),
            tracked_levels: TRACKED_LEVELS,
            next_px: Vec::with_capacity(max_features),
            status: Vec::with_capacity(max_features),
            corners: Vec::with_capacity(max_features),
            keyframe_count: 0,
            flow_scratch: [
                Vec::with_capacity(max_features),
                Vec::with_capacity(max_features),
            ],
        })
    }

    /// Builds the pyramid of `image` and tracks the live features into it. Returns how many
    /// survived (0 for the first frame). On error the tracks are dropped.
    pub fn track(&mut self, image: &ImageView<'_>) -> Result<usize, TrackError> {
        if let Err(e) = self.pyr_cur.build(image) {
            self.reset();
            return Err(e.into());
        }
        if !self.has_prev {
            std::mem::swap(&mut self.pyr_prev, &mut self.pyr_cur);
            self.has_prev = true;
            self.clear_tracks();
            return Ok(0);
        }
        let n = self.cur_px.len();
        self.next_px.clear();
        self.status.clear();
        for i in 0..n {
            self.next_px.push(self.cur_px[i] + self.flow_px[i]);
            self.status.push(TrackStatus::Tracked);
        }
        let result = self.klt.track_with_levels(
            &self.pyr_prev,
            &self.pyr_cur,
            &self.cur_px,
            &mut self.next_px,
            &mut self.status,
            true,
            &self.levels,
        );
        std::mem::swap(&mut self.pyr_prev, &mut self.pyr_cur);
        if let Err(e) = result {
            self.clear_tracks();
            return Err(e.into());
        }
        let mut kept = 0;
        for i in 0..n {
            let p = self.next_px[i];
            if self.status[i] == TrackStatus::Tracked && p.x.is_finite() && p.y.is_finite() {
                self.flow_px[kept] = p - self.cur_px[i];
                self.cur_px[kept] = p;
                self.kf_px[kept] = self.kf_px[i];
                self.birth_px[kept] = self.birth_px[i];
                self.birth_serial[kept] = self.birth_serial[i];
                self.track_id[kept] = self.track_id[i];
                self.levels[kept] = self.tracked_levels;
                kept += 1;
            }
        }
        self.truncate(kept);
        Ok(kept)
    }

    /// Drops every track and forgets the previous frame (re-initialization).
    pub fn reset(&mut self) {
        self.has_prev = false;
        self.clear_tracks();
    }

    fn clear_tracks(&mut self) {
        self.cur_px.clear();
        self.kf_px.clear();
        self.birth_px.clear();
        self.birth_serial.clear();
        self.track_id.clear();
        self.flow_px.clear();
        self.levels.clear();
        self.keyframe_count = 0;
    }

    /// Keeps only the tracks whose `keep[i]` is true (e.g. RANSAC inliers).
    pub fn retain(&mut self, keep: &[bool]) {
        let mut kept = 0;
        for i in 0..self.cur_px.len() {
            if keep.get(i).copied().unwrap_or(false) {
                self.cur_px[kept] = self.cur_px[i];
                self.kf_px[kept] = self.kf_px[i];
                self.birth_px[kept] = self.birth_px[i];
                self.birth_serial[kept] = self.birth_serial[i];
                self.track_id[kept] = self.track_id[i];
                self.flow_px[kept] = self.flow_px[i];
                self.levels[kept] = self.levels[i];
                kept += 1;
            }
        }
        self.truncate(kept);
    }

    fn truncate(&mut self, len: usize) {
        self.cur_px.truncate(len);
        self.kf_px.truncate(len);
        self.birth_px.truncate(len);
        self.birth_serial.truncate(len);
        self.track_id.truncate(len);
        self.flow_px.truncate(len);
        self.levels.truncate(len);
    }

    /// Makes the last frame the keyframe and tops the tracks up with new corners (paper step
    /// 1). New tracks predict the median flow of the old ones. Returns the track count.
    pub fn set_keyframe(&mut self) -> Result<usize, TrackError> {
        self.keyframe_serial = self.keyframe_serial.wrapping_add(1);
        self.kf_px.clear();
        self.kf_px.extend_from_slice(&self.cur_px);
        if !self.has_prev {
            self.keyframe_count = 0;
            return Ok(0);
        }
        let median_flow = median_flow(&self.flow_px, &mut self.flow_scratch);
        if let Some(level) = self.pyr_prev.level(0) {
            self.detector
                .detect(level, &self.cur_px, &mut self.corners)?;
            for c in &self.corners {
                if self.cur_px.len() >= self.max_features {
                    break;
                }
                self.cur_px.push(c.position_px);
                self.kf_px.push(c.position_px);
                self.birth_px.push(c.position_px);
                self.birth_serial.push(self.keyframe_serial);
                self.track_id.push(self.next_track_id);
                self.next_track_id = self.next_track_id.wrapping_add(1);
                self.flow_px.push(median_flow);
                self.levels.push(u8::MAX);
            }
        }
        self.keyframe_count = self.cur_px.len();
        Ok(self.cur_px.len())
    }

    /// Median length of the last frame-to-frame track displacement, pixels (`INFINITY`
    /// without tracks).
    pub fn median_flow_norm_px(&mut self) -> f32 {
        if self.flow_px.is_empty() {
            return f32::INFINITY;
        }
        let f = median_flow(&self.flow_px, &mut self.flow_scratch);
        f.norm()
    }

    /// Positions in the last frame.
    pub fn current_px(&self) -> &[Point2<f32>] {
        &self.cur_px
    }

    /// Positions of the same tracks in the keyframe.
    pub fn keyframe_px(&self) -> &[Point2<f32>] {
        &self.kf_px
    }

    /// Positions of the same tracks in the keyframe each was born in.
    pub fn birth_px(&self) -> &[Point2<f32>] {
        &self.birth_px
    }

    /// Serial of the keyframe each track was born in (see [`Self::keyframe_serial`]).
    pub fn birth_serial(&self) -> &[u32] {
        &self.birth_serial
    }

    /// Identity of each track, unique over the tracker's life (wraps after 2³² tracks).
    pub fn track_id(&self) -> &[u32] {
        &self.track_id
    }

    /// Serial of the current keyframe: it grows by one at every [`Self::set_keyframe`], so a
    /// track born `n` keyframes ago has `birth_serial = keyframe_serial − n`.
    pub fn keyframe_serial(&self) -> u32 {
        self.keyframe_serial
    }

    /// Tracks alive when the keyframe was set.
    pub fn keyframe_count(&self) -> usize {
        self.keyframe_count
    }

    /// Whether a previous frame exists.
    pub fn has_previous_frame(&self) -> bool {
        self.has_prev
    }
}

/// Per-axis median of `flow` (upper median for an even count), using `scratch` (no
/// allocation up to its capacity).
fn median_flow(flow: &[Vector2<f32>], scratch: &mut [Vec<f32>; 2]) -> Vector2<f32> {
    if flow.is_empty() {
        return Vector2::zeros();
    }
    let [xs, ys] = scratch;
    xs.clear();
    ys.clear();
    xs.extend(flow.iter().map(|f| f.x));
    ys.extend(flow.iter().map(|f| f.y));
    let mid = flow.len() / 2;
    let x = *xs.select_nth_unstable_by(mid, f32::total_cmp).1;
    let y = *ys.select_nth_unstable_by(mid, f32::total_cmp).1;
    Vector2::new(x, y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hopnav_vision::synthetic::{AffineWarp, BlobTexture};

    const SIZE_PX: usize = 160;

    fn frame(texture: &BlobTexture, shift_px: f64) -> Vec<u8> {
        let mut image = vec![0u8; SIZE_PX * SIZE_PX];
        texture.render(
            SIZE_PX,
            SIZE_PX,
            &AffineWarp::translation(shift_px, 0.5 * shift_px),
            &mut image,
        );
        image
    }

    #[test]
    fn a_track_keeps_its_birth_keyframe_and_position_across_keyframes() {
        let texture = BlobTexture::random(SIZE_PX, SIZE_PX, 300, 7);
        let mut tracks = FeatureTracks::new(SIZE_PX, SIZE_PX, 150).unwrap();
        let first = frame(&texture, 0.0);
        tracks
            .track(&ImageView::packed(&first, SIZE_PX, SIZE_PX).unwrap())
            .unwrap();
        tracks.set_keyframe().unwrap();
        let born_serial = tracks.keyframe_serial();
        assert!(tracks.birth_serial().iter().all(|&s| s == born_serial));
        assert_eq!(tracks.birth_px(), tracks.keyframe_px());
        let born_px: Vec<Point2<f32>> = tracks.birth_px().to_vec();
        for step in 1..=6 {
            let image = frame(&texture, 1.5 * f64::from(step));
            tracks
                .track(&ImageView::packed(&image, SIZE_PX, SIZE_PX).unwrap())
                .unwrap();
            if step % 2 == 0 {
                // Drop every fifth track, as RANSAC would, then set a keyframe.
                let keep: Vec<bool> = (0..tracks.current_px().len()).map(|i| i % 5 != 0).collect();
                tracks.retain(&keep);
                tracks.set_keyframe().unwrap();
            }
        }
        assert_eq!(tracks.keyframe_serial(), born_serial + 3);
        let (births, serials) = (tracks.birth_px(), tracks.birth_serial());
        assert_eq!(births.len(), tracks.current_px().len());
        let old: Vec<usize> = (0..serials.len())
            .filter(|&i| serials[i] == born_serial)
            .collect();
        assert!(
            old.len() > 20,
            "only {} tracks from the first keyframe",
            old.len()
        );
        for &i in &old {
            // Born in the first frame: the image moved by (9, 4.5) px since.
            let moved = tracks.current_px()[i] - births[i];
            assert!(
                (moved.x - 9.0).abs() < 0.5 && (moved.y - 4.5).abs() < 0.5,
                "{moved:?}"
            );
            assert!(born_px.contains(&births[i]));
        }
        // Corners added at later keyframes were born there.
        assert!(
            serials
                .iter()
                .all(|&s| s >= born_serial && s <= born_serial + 3)
        );
        tracks.reset();
        assert!(tracks.birth_px().is_empty() && tracks.birth_serial().is_empty());
    }
}
