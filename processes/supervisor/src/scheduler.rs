//! Which process may step which frame, and when a frame is finished end to end.
//!
//! Stages run in order within a frame: stage s+1 is released for frame k once every live
//! stage-s process has completed frame k. A frame is done when every live process has
//! completed it; its end-to-end latency runs from the tick to the last completion stamp.
//! In lockstep a process that is down blocks the pipeline until it is back (then it is
//! re-released the frame it missed); in real time it is skipped so the clock keeps going.

use std::collections::BTreeMap;

/// A frame release for one process.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Release {
    /// Slot of the process in the table.
    pub slot: usize,
    /// Frame to step.
    pub frame_index: u64,
}

/// A frame that finished (or was given up on).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameOutcome {
    /// The frame.
    pub frame_index: u64,
    /// Tick to last completion, nanoseconds; `None` if the frame was abandoned.
    pub end_to_end_ns: Option<u64>,
    /// True if some process skipped it or was down (real-time mode only).
    pub degraded: bool,
}

#[derive(Debug, Clone)]
struct OpenFrame {
    tick_stamp_ns: u64,
    completed_stamp_ns: Vec<Option<u64>>,
    degraded: bool,
}

#[derive(Debug, Clone, Copy, Default)]
struct SlotState {
    live: bool,
    last_completed: Option<u64>,
    last_released: Option<u64>,
}

/// The release and completion logic of the frame clock.
#[derive(Debug, Clone)]
pub struct FrameScheduler {
    stages: Vec<Vec<usize>>,
    stage_of_slot: Vec<usize>,
    slots: Vec<SlotState>,
    open_frames: BTreeMap<u64, OpenFrame>,
    lockstep: bool,
    max_open_frames: usize,
}

impl FrameScheduler {
    /// A scheduler for processes whose stage numbers are `stage_numbers[slot]`.
    pub fn new(stage_numbers: &[u32], lockstep: bool) -> Self {
        let mut distinct: Vec<u32> = stage_numbers.to_vec();
        distinct.sort_unstable();
        distinct.dedup();
        let stage_of_slot: Vec<usize> = stage_numbers
            .iter()
            .map(|number| distinct.iter().position(|d| d == number).unwrap_or(0))
            .collect();
        let mut stages = vec![Vec::new(); distinct.len()];
        for (slot, stage) in stage_of_slot.iter().enumerate() {
            stages[*stage].push(slot);
        }
        Self {
            stages,
            stage_of_slot,
            slots: vec![SlotState::default(); stage_numbers.len()],
            open_frames: BTreeMap::new(),
            lockstep,
            max_open_frames: 8,
        }
    }

    /// Frames started but not yet finished.
    pub fn open_frame_count(&self) -> usize {
        self.open_frames.len()
    }

    /// CLOCK_MONOTONIC tick stamp of an open frame.
    pub fn tick_stamp_ns(&self, frame_index: u64) -> Option<u64> {
        self.open_frames
            .get(&frame_index)
            .map(|open| open.tick_stamp_ns)
    }

    /// True when `frame_index` finished (or was never started).
    pub fn is_done(&self, frame_index: u64) -> bool {
        !self.open_frames.contains_key(&frame_index)
    }

    /// Starts `frame_index` at `tick_stamp_ns`: releases stage 0. In real time, frames left
    /// open too long are abandoned and returned.
    pub fn start_frame(
        &mut self,
        frame_index: u64,
        tick_stamp_ns: u64,
    ) -> (Vec<Release>, Vec<FrameOutcome>) {
        self.open_frames.insert(
            frame_index,
            OpenFrame {
                tick_stamp_ns,
                completed_stamp_ns: vec![None; self.slots.len()],
                degraded: false,
            },
        );
        let mut abandoned = Vec::new();
        while self.open_frames.len() > self.max_open_frames {
            if let Some((frame, _)) = self.open_frames.pop_first() {
                abandoned.push(FrameOutcome {
                    frame_index: frame,
                    end_to_end_ns: None,
                    degraded: true,
                });
            }
        }
        (self.releasable(), abandoned)
    }

    /// Records that `slot` completed `frame_index` at `stamp_ns`.
    pub fn on_completed(
        &mut self,
        slot: usize,
        frame_index: u64,
        stamp_ns: u64,
    ) -> (Vec<Release>, Vec<FrameOutcome>) {
        if let Some(state) = self.slots.get_mut(slot) {
            state.last_completed = Some(
                state
                    .last_completed
                    .map_or(frame_index, |f| f.max(frame_index)),
            );
        }
        for (frame, open) in self.open_frames.range_mut(..=frame_index) {
            if let Some(entry) = open.completed_stamp_ns.get_mut(slot)
                && entry.is_none()
            {
                *entry = Some(stamp_ns);
                open.degraded |= *frame != frame_index;
            }
        }
        let outcomes = self.finish_frames();
        (self.releasable(), outcomes)
    }

    /// Marks `slot` as live (ready) or down; returns releases this allows.
    pub fn set_live(&mut self, slot: usize, live: bool) -> (Vec<Release>, Vec<FrameOutcome>) {
        if let Some(state) = self.slots.get_mut(slot) {
            state.live = live;
            // A restarted process has lost what it was released; release it again.
            state.last_released = state.last_completed;
        }
        if !live && !self.lockstep {
            for open in self.open_frames.values_mut() {
                open.degraded = true;
            }
        }
        let outcomes = self.finish_frames();
        (self.releasable(), outcomes)
    }

    fn slot_done(&self, slot: usize, frame_index: u64, open: &OpenFrame) -> bool {
        let state = &self.slots[slot];
        open.completed_stamp_ns[slot].is_some()
            || state.last_completed.is_some_and(|f| f >= frame_index)
            || (!state.live && !self.lockstep)
    }

    fn finish_frames(&mut self) -> Vec<FrameOutcome> {
        let mut outcomes = Vec::new();
        let done: Vec<u64> = self
            .open_frames
            .iter()
            .filter(|(frame, open)| {
                (0..self.slots.len()).all(|slot| self.slot_done(slot, **frame, open))
            })
            .map(|(frame, _)| *frame)
            .collect();
        for frame in done {
            if let Some(open) = self.open_frames.remove(&frame) {
                let last_ns = open.completed_stamp_ns.iter().flatten().max().copied();
                outcomes.push(FrameOutcome {
                    frame_index: frame,
                    end_to_end_ns: last_ns.map(|ns| ns.saturating_sub(open.tick_stamp_ns)),
                    degraded: open.degraded || open.completed_stamp_ns.iter().any(Option::is_none),
                });
            }
        }
        outcomes
    }

    /// Releases every live process whose upstream stages finished a newer frame than it was
    /// last released.
    fn releasable(&mut self) -> Vec<Release> {
        let mut releases = Vec::new();
        let Some(newest) = self.open_frames.keys().next_back().copied() else {
            return releases;
        };
        for slot in 0..self.slots.len() {
            if !self.slots[slot].live {
                continue;
            }
            // Newest open frame this slot's upstream stages have all finished.
            let stage = self.stage_of_slot[slot];
            let ready_frame = self
                .open_frames
                .iter()
                .rev()
                .map(|(frame, open)| (*frame, open))
                .find(|(frame, open)| {
                    self.stages[..stage]
                        .iter()
                        .flatten()
                        .all(|upstream| self.slot_done(*upstream, *frame, open))
                })
                .map(|(frame, _)| frame);
            let Some(frame) = ready_frame else { continue };
            let frame = frame.min(newest);
            let state = &mut self.slots[slot];
            let already = state.last_released.is_some_and(|f| f >= frame)
                || state.last_completed.is_some_and(|f| f >= frame);
            if !already {
                state.last_released = Some(frame);
                releases.push(Release {
                    slot,
                    frame_index: frame,
                });
            }
        }
        releases
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn released(releases: &[Release]) -> Vec<(usize, u64)> {
        releases.iter().map(|r| (r.slot, r.frame_index)).collect()
    }

    fn live_scheduler(stages: &[u32], lockstep: bool) -> FrameScheduler {
        let mut scheduler = FrameScheduler::new(stages, lockstep);
        for slot in 0..stages.len() {
            scheduler.set_live(slot, true);
        }
        scheduler
    }

    #[test]
    fn stages_release_in_order_and_frame_latency_spans_tick_to_last_completion() {
        let mut scheduler = live_scheduler(&[0, 1, 1, 3], true);
        let (releases, _) = scheduler.start_frame(0, 1_000);
        assert_eq!(released(&releases), vec![(0, 0)]);
        let (releases, done) = scheduler.on_completed(0, 0, 2_000);
        assert_eq!(released(&releases), vec![(1, 0), (2, 0)]);
        assert!(done.is_empty());
        let (releases, _) = scheduler.on_completed(1, 0, 3_000);
        assert!(
            releases.is_empty(),
            "stage 3 waits for both stage-1 processes"
        );
        let (releases, _) = scheduler.on_completed(2, 0, 3_500);
        assert_eq!(released(&releases), vec![(3, 0)]);
        let (_, done) = scheduler.on_completed(3, 0, 9_000);
        assert_eq!(
            done,
            vec![FrameOutcome {
                frame_index: 0,
                end_to_end_ns: Some(8_000),
                degraded: false
            }]
        );
        assert!(scheduler.is_done(0));
    }

    #[test]
    fn lockstep_waits_for_a_restarted_process_and_re_releases_its_frame() {
        let mut scheduler = live_scheduler(&[0, 1], true);
        scheduler.start_frame(0, 0);
        scheduler.on_completed(0, 0, 10);
        scheduler.set_live(1, false);
        assert!(!scheduler.is_done(0), "lockstep blocks on the dead process");
        let (releases, _) = scheduler.set_live(1, true);
        assert_eq!(released(&releases), vec![(1, 0)]);
        let (_, done) = scheduler.on_completed(1, 0, 50);
        assert_eq!(done.len(), 1);
        assert!(!done[0].degraded);
    }

    #[test]
    fn real_time_skips_a_dead_process_and_marks_the_frame_degraded() {
        let mut scheduler = live_scheduler(&[0, 1], false);
        scheduler.start_frame(0, 0);
        scheduler.set_live(1, false);
        let (releases, done) = scheduler.on_completed(0, 0, 10);
        assert!(releases.is_empty());
        assert_eq!(done.len(), 1);
        assert!(done[0].degraded);
    }

    #[test]
    fn a_late_stage_jumps_to_the_newest_ready_frame() {
        let mut scheduler = live_scheduler(&[0, 1], false);
        scheduler.start_frame(0, 0);
        scheduler.on_completed(0, 0, 10); // releases slot 1 for frame 0
        scheduler.start_frame(1, 100);
        let (releases, _) = scheduler.on_completed(0, 1, 110);
        assert_eq!(released(&releases), vec![(1, 1)]);
        // Slot 1 finishes frame 1 directly: frame 0 counts as done but degraded.
        let (_, done) = scheduler.on_completed(1, 1, 150);
        let frames: Vec<_> = done.iter().map(|o| (o.frame_index, o.degraded)).collect();
        assert_eq!(frames, vec![(0, true), (1, false)]);
    }

    #[test]
    fn frames_open_too_long_are_abandoned() {
        let mut scheduler = live_scheduler(&[0], false);
        let mut abandoned = Vec::new();
        for frame in 0..12 {
            let (_, outcomes) = scheduler.start_frame(frame, frame * 100);
            abandoned.extend(outcomes);
        }
        assert_eq!(abandoned.len(), 4);
        assert!(abandoned.iter().all(|o| o.end_to_end_ns.is_none()));
    }
}
