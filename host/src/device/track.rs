//! Sequence and device-time bookkeeping of one stream: unwraps the u32 counters, spots gaps,
//! duplicates and device restarts. Shared by the live driver and by replay, so a file re-decoded
//! later gets exactly the gaps the live logger saw.

use super::GapKind;

/// What one sample frame means for the stream.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// A frame received twice: drop it.
    Duplicate,
    /// A frame to keep; `gap` is set when frames are missing before it (or the device
    /// restarted), `t_device_us` is its unwrapped device time within the session.
    Keep {
        gap: Option<GapKind>,
        t_device_us: u64,
        session: u32,
    },
}

/// The bookkeeping state.
#[derive(Debug, Default, Clone)]
pub struct Tracker {
    last_seq: Option<u32>,
    last_t: u32,
    t64: u64,
    session: u32,
}

impl Tracker {
    pub fn session(&self) -> u32 {
        self.session
    }

    pub fn last_seq(&self) -> Option<u32> {
        self.last_seq
    }

    /// Start a new session (after a reconnection): unwrapping starts again from the next frame.
    pub fn new_session(&mut self) {
        self.session += 1;
        self.last_seq = None;
    }

    /// Account for frame `seq` sent at device time `t_us` with `dropped` frames reported dropped
    /// by the device.
    pub fn step(&mut self, seq: u32, t_us: u32, dropped: u16) -> Step {
        let mut gap = None;
        if let Some(last) = self.last_seq {
            let d = seq.wrapping_sub(last);
            if d == 0 {
                return Step::Duplicate;
            }
            if d >= 1 << 31 {
                gap = Some(GapKind::DeviceRestart {
                    last_seq: last,
                    new_seq: seq,
                });
                self.session += 1;
                self.last_seq = None;
            } else if d > 1 {
                let missing = u64::from(d - 1);
                let dropped = u64::from(dropped);
                gap = Some(GapKind::Sequence {
                    after_seq: last,
                    missing,
                    lost_on_link: missing.saturating_sub(dropped),
                    dropped_by_device: dropped.min(missing),
                });
            }
        }
        if self.last_seq.is_some() {
            self.t64 += u64::from(t_us.wrapping_sub(self.last_t));
        } else {
            self.t64 = u64::from(t_us);
        }
        self.last_seq = Some(seq);
        self.last_t = t_us;
        Step::Keep {
            gap,
            t_device_us: self.t64,
            session: self.session,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unwraps_time_and_sequence_across_the_u32_wrap() {
        let mut t = Tracker::default();
        assert!(
            matches!(t.step(u32::MAX, u32::MAX - 5, 0), Step::Keep { gap: None, t_device_us, .. } if t_device_us == u64::from(u32::MAX - 5))
        );
        match t.step(0, 4, 0) {
            Step::Keep {
                gap: None,
                t_device_us,
                session: 0,
            } => assert_eq!(t_device_us, u64::from(u32::MAX) + 5),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn gaps_split_link_loss_from_device_drops_and_duplicates_are_dropped() {
        let mut t = Tracker::default();
        t.step(10, 0, 0);
        assert_eq!(t.step(10, 0, 0), Step::Duplicate);
        match t.step(15, 50, 3) {
            Step::Keep {
                gap:
                    Some(GapKind::Sequence {
                        missing: 4,
                        lost_on_link: 1,
                        dropped_by_device: 3,
                        after_seq: 10,
                    }),
                ..
            } => {}
            other => panic!("{other:?}"),
        }
        match t.step(2, 0, 0) {
            Step::Keep {
                gap:
                    Some(GapKind::DeviceRestart {
                        last_seq: 15,
                        new_seq: 2,
                    }),
                session: 1,
                ..
            } => {}
            other => panic!("{other:?}"),
        }
    }
}
