//! The STM32 independent watchdog's (IWDG) setting for a timeout: its counter runs from the LSI
//! RC oscillator through a prescaler of 4·2^PR (PR = 0..=6, dividers 4..=256) and counts down
//! from a 12-bit reload value RL, so the timeout is (RL + 1)·4·2^PR / f_LSI (RM0383 §15.3).
//! Board-independent arithmetic, tested on the host; the board writes the registers.

/// Largest reload value (12 bits).
pub const MAX_RELOAD: u16 = 0x0FFF;
/// Largest prescaler code (divider 256).
pub const MAX_PRESCALER: u8 = 6;

/// Register values for one timeout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IwdgSetting {
    /// IWDG_PR.PR: the divider is 4·2^PR.
    pub prescaler: u8,
    /// IWDG_RLR.RL.
    pub reload: u16,
}

impl IwdgSetting {
    /// The finest setting (smallest divider) whose timeout at `lsi_hz` is the nearest to
    /// `timeout_ms`; None if the timeout is zero or longer than the largest divider reaches.
    pub const fn for_timeout(timeout_ms: u32, lsi_hz: u32) -> Option<Self> {
        if timeout_ms == 0 || lsi_hz == 0 {
            return None;
        }
        // LSI cycles the timeout spans (u64: 32 s at 47 kHz overflows nothing, but be sure).
        let cycles = timeout_ms as u64 * lsi_hz as u64 / 1000;
        let mut prescaler = 0;
        while prescaler <= MAX_PRESCALER {
            let divider = 4u64 << prescaler;
            // Rounded to the nearest count.
            let counts = (cycles + divider / 2) / divider;
            if counts >= 1 && counts <= MAX_RELOAD as u64 + 1 {
                return Some(Self {
                    prescaler,
                    reload: (counts - 1) as u16,
                });
            }
            prescaler += 1;
        }
        None
    }

    /// LSI cycles per count.
    pub const fn divider(self) -> u32 {
        4 << self.prescaler
    }

    /// The timeout this setting gives at `lsi_hz`, in microseconds.
    pub const fn timeout_us(self, lsi_hz: u32) -> u64 {
        (self.reload as u64 + 1) * self.divider() as u64 * 1_000_000 / lsi_hz as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_second_at_the_nominal_32_khz() {
        // 250 ms × 32 kHz = 8000 LSI cycles: divider 4, 2000 counts.
        let s = IwdgSetting::for_timeout(250, 32_000).unwrap();
        assert_eq!(
            s,
            IwdgSetting {
                prescaler: 0,
                reload: 1999
            }
        );
        assert_eq!(s.timeout_us(32_000), 250_000);
        // The same registers at the datasheet's LSI extremes (17 and 47 kHz).
        assert_eq!(s.timeout_us(47_000), 170_212);
        assert_eq!(s.timeout_us(17_000), 470_588);
    }

    #[test]
    fn long_timeouts_take_a_coarser_prescaler_and_the_limits_hold() {
        // 1 s at 32 kHz: 32000 cycles, 8000 counts of 4 (too many), 4000 counts of 8.
        assert_eq!(
            IwdgSetting::for_timeout(1000, 32_000),
            Some(IwdgSetting {
                prescaler: 1,
                reload: 3999
            })
        );
        // The longest: 4096 counts of 256 at 32 kHz = 32.768 s.
        assert_eq!(
            IwdgSetting::for_timeout(32_768, 32_000),
            Some(IwdgSetting {
                prescaler: MAX_PRESCALER,
                reload: MAX_RELOAD
            })
        );
        assert_eq!(IwdgSetting::for_timeout(40_000, 32_000), None);
        assert_eq!(IwdgSetting::for_timeout(0, 32_000), None);
    }
}
