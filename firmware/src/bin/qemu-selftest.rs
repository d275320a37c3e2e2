//! On-target tests under QEMU `mps2-an386` (Cortex-M4F, hard-float): the pieces that must run on
//! the real core. Results go out over semihosting; the exit code is the verdict (0 = all passed).
//!
//! Run: `scripts/test-firmware.sh` (builds it, then runs `qemu-system-arm -machine mps2-an386
//! -semihosting-config enable=on,target=native -icount shift=0 -kernel <elf>`).
#![cfg_attr(target_os = "none", no_std, no_main)]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

firmware::mps2_an386_binary!();

#[cfg(target_os = "none")]
mod target {
    use core::cell::RefCell;
    use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
    use cortex_m_rt::{entry, exception};
    use cortex_m_semihosting::hprintln;
    use critical_section::Mutex;
    use firmware::board::mps2_an386 as board;
    use firmware::dsp::{round_to_code, Butterworth, FilterBank};
    use firmware::stream::{Acquirer, Overruns, RawSample, SampleQueue, QUEUE_LEN};
    use protocol::FilterConfig;

    static FAILED: AtomicU32 = AtomicU32::new(0);
    static PASSED: AtomicU32 = AtomicU32::new(0);

    fn check(name: &str, ok: bool) {
        hprintln!("{} {}", if ok { "ok  " } else { "FAIL" }, name);
        let counter = if ok { &PASSED } else { &FAILED };
        counter.fetch_add(1, Ordering::Relaxed);
    }

    /// f64 (soft-float) reference of the same Butterworth design, to check the FPU path.
    fn reference(order: u8, ratio: f64, x: &[f32], y: &mut [f64]) {
        let k = libm::tan(core::f64::consts::PI * ratio);
        let mut input = [0f64; 2048];
        for (i, v) in x.iter().enumerate() {
            input[i] = f64::from(*v);
        }
        let n = f64::from(order);
        let mut signal = &mut input[..x.len()];
        for i in 0..order / 2 {
            let q = 1.0
                / (2.0 * libm::cos((2.0 * f64::from(i) + 1.0) * core::f64::consts::PI / (2.0 * n)));
            let d = 1.0 + k / q + k * k;
            let b0 = k * k / d;
            let (b1, b2, a1, a2) = (
                2.0 * b0,
                b0,
                2.0 * (k * k - 1.0) / d,
                (1.0 - k / q + k * k) / d,
            );
            let x0 = signal[0];
            let mut s2 = (b2 - a2) * x0;
            let mut s1 = (b1 - a1) * x0 + s2;
            for v in signal.iter_mut() {
                let out = b0 * *v + s1;
                s1 = b1 * *v - a1 * out + s2;
                s2 = b2 * *v - a2 * out;
                *v = out;
            }
            signal = &mut signal[..];
        }
        y.copy_from_slice(&input[..x.len()]);
    }

    fn dsp_tests() {
        let mut x = [0f32; 2048];
        let mut state = 0x2545_F491_u32;
        for (i, v) in x.iter_mut().enumerate() {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            *v = 0.5 * libm::sinf(i as f32 * 0.05) + 0.4 * ((state as f32 / u32::MAX as f32) - 0.5);
        }
        let mut y64 = [0f64; 2048];
        for (order, ratio) in [(2u8, 0.01f32), (4, 0.01), (4, 0.1), (2, 0.4)] {
            let config = FilterConfig {
                smoother_alpha: 1.0,
                butterworth_order: order,
                cutoff_hz: ratio * 1000.0,
            };
            let mut f = FilterBank::build(&config, 1000.0).unwrap();
            reference(order, f64::from(ratio), &x, &mut y64);
            let worst = x
                .iter()
                .zip(&y64)
                .map(|(&xi, &r)| libm::fabs(f64::from(f.step([xi, -xi, xi])[0]) - r))
                .fold(0.0, f64::max);
            hprintln!(
                "     butterworth order {} fc/fs {}: max |f32 - f64| = {}",
                order,
                ratio,
                worst
            );
            check(
                "butterworth f32 on the FPU within 2e-5 of f64",
                worst <= 2e-5,
            );
        }
        let config = FilterConfig {
            smoother_alpha: 0.05,
            butterworth_order: 0,
            cutoff_hz: 0.0,
        };
        let mut s = FilterBank::build(&config, 1000.0).unwrap();
        s.step([0.0; 3]);
        let mut worst = 0.0f64;
        for n in 1..400 {
            let exact = 1.0 - libm::pow(0.95, f64::from(n));
            worst = worst.max(libm::fabs(f64::from(s.step([1.0; 3])[2]) - exact));
        }
        check(
            "smoother step response within 1e-5 of closed form",
            worst <= 1e-5,
        );
        let config = FilterConfig {
            smoother_alpha: 1.0,
            butterworth_order: 2,
            cutoff_hz: 450.0,
        };
        let refused = FilterBank::build(&config, 1000.0).is_err();
        check("cut-off at 0.45 fs refused", refused);
        asm_paths_match_the_portable_code(&x);
    }

    /// The bank's three-channel section is hand-written VLDM/VMLA/VSTM on this core; it must give
    /// the very bits of the portable single-channel `Biquad::step` cascade, on every channel.
    fn asm_paths_match_the_portable_code(x: &[f32]) {
        let mut bank = FilterBank::build(
            &FilterConfig {
                smoother_alpha: 1.0,
                butterworth_order: 4,
                cutoff_hz: 37.0,
            },
            1000.0,
        )
        .unwrap();
        let design = Butterworth::design(4, 0.037).unwrap();
        let prime = |k: usize| {
            let section = &design.sections()[k];
            [
                section.primed(x[0]),
                section.primed(-x[0]),
                section.primed(2.0 * x[0]),
            ]
        };
        let mut states = [prime(0), prime(1)];
        let mut identical = true;
        for &xi in x {
            let got = bank.step([xi, -xi, 2.0 * xi]);
            let mut want = [xi, -xi, 2.0 * xi];
            for (section, st) in design.sections().iter().zip(states.iter_mut()) {
                for ch in 0..3 {
                    want[ch] = section.step(&mut st[ch], want[ch]);
                }
            }
            identical &= got.map(f32::to_bits) == want.map(f32::to_bits);
        }
        check(
            "butterworth asm section bit-identical to Biquad::step",
            identical,
        );
        filter_on_codes_matches_step_then_round(x);
        round_to_code_cases();
    }

    /// The filter on codes is one asm block; it must equal the float filter then rounding.
    fn filter_on_codes_matches_step_then_round(x: &[f32]) {
        let config = FilterConfig {
            smoother_alpha: 1.0,
            butterworth_order: 4,
            cutoff_hz: 37.0,
        };
        let mut codes = FilterBank::build(&config, 1000.0).unwrap();
        let mut floats = FilterBank::build(&config, 1000.0).unwrap();
        let mut same = true;
        for (i, &xi) in x.iter().enumerate() {
            let c = (xi * 6.0e6) as i32;
            let sample = [c, -c, protocol::CODE_MAX - i as i32];
            let want = floats.step(sample.map(|v| v as f32)).map(round_to_code);
            same &= codes.step_codes(sample) == want;
        }
        check(
            "filter on codes (one asm block) equals step then round_to_code",
            same,
        );
    }

    /// `round_to_code` uses VCVTR here: nearest, ties to even, clamped to 24 bits.
    fn round_to_code_cases() {
        let cases = [
            (2.5, 2),
            (3.5, 4),
            (-2.5, -2),
            (-2.6, -3),
            (0.49, 0),
            (1.0e9, protocol::CODE_MAX),
            (-1.0e9, protocol::CODE_MIN),
            (f32::NAN, 0),
        ];
        let rounded = cases.iter().all(|&(y, code)| round_to_code(y) == code);
        check(
            "round_to_code: nearest, ties to even, clamped, NaN 0",
            rounded,
        );
    }

    // --- queue under interrupt pressure ---------------------------------------------------------
    static mut QUEUE: SampleQueue = SampleQueue::new();
    static OVERRUNS: Overruns = Overruns::new();
    static ACQUIRER: Mutex<RefCell<Option<Acquirer<'static>>>> = Mutex::new(RefCell::new(None));
    static PUSHED: AtomicU32 = AtomicU32::new(0);
    static RUNNING: AtomicBool = AtomicBool::new(false);

    #[exception]
    fn SysTick() {
        if !RUNNING.load(Ordering::Relaxed) {
            return;
        }
        let index = PUSHED.fetch_add(1, Ordering::Relaxed);
        critical_section::with(|cs| {
            if let Some(acq) = ACQUIRER.borrow_ref_mut(cs).as_mut() {
                acq.push(RawSample {
                    index,
                    codes: [index as i32; 4],
                    read_error: false,
                });
            }
        });
    }

    /// Drain `target` samples with `work` busy-loop iterations per sample; returns
    /// (popped, samples missing from the index sequence, overruns counted by the producer).
    fn pressure(
        consumer: &mut firmware::stream::Drain<'static>,
        target: u32,
        work: u32,
    ) -> (u32, u32, u32) {
        let mut popped = 0;
        let mut gaps = 0;
        let mut next: Option<u32> = None;
        RUNNING.store(true, Ordering::Relaxed);
        while popped < target {
            if let Some(s) = consumer.dequeue() {
                if s.codes != [s.index as i32; 4] {
                    return (popped, u32::MAX, 0); // torn sample
                }
                if let Some(n) = next {
                    gaps += s.index.wrapping_sub(n);
                }
                next = Some(s.index.wrapping_add(1));
                popped += 1;
                for _ in 0..work {
                    cortex_m::asm::nop();
                }
            }
        }
        RUNNING.store(false, Ordering::Relaxed);
        // Drain what is still queued, then count the samples dropped after the last one queued:
        // every sample pushed is either popped or counted as an overrun.
        while let Some(s) = consumer.dequeue() {
            if let Some(n) = next {
                gaps += s.index.wrapping_sub(n);
            }
            next = Some(s.index.wrapping_add(1));
        }
        let trailing = next.map_or(0, |n| PUSHED.load(Ordering::Relaxed).wrapping_sub(n));
        (popped, gaps + trailing, OVERRUNS.take())
    }

    fn queue_tests(syst: &mut cortex_m::peripheral::SYST) {
        // SAFETY: the queue is split once, before the interrupt that uses the producer starts.
        let (producer, mut consumer) = unsafe { (*core::ptr::addr_of_mut!(QUEUE)).split() };
        critical_section::with(|cs| {
            ACQUIRER
                .borrow_ref_mut(cs)
                .replace(Acquirer::new(producer, &OVERRUNS))
        });
        // An interrupt every 100 ticks (~4000 instructions under icount): heavy pressure.
        board::start_sample_clock(syst, 100);
        let (popped, gaps, overruns) = pressure(&mut consumer, 5000, 0);
        PUSHED.store(0, Ordering::Relaxed); // the second run starts its index sequence at 0
        hprintln!(
            "     fast consumer: popped {} gaps {} overruns {}",
            popped,
            gaps,
            overruns
        );
        check(
            "fast consumer sees every sample in order, no overrun",
            gaps == 0 && overruns == 0,
        );
        let (popped, gaps, overruns) = pressure(&mut consumer, 2000, 3000);
        hprintln!(
            "     slow consumer: popped {} gaps {} overruns {} (queue {})",
            popped,
            gaps,
            overruns,
            QUEUE_LEN - 1
        );
        check(
            "slow consumer: every gap is a counted overrun",
            gaps > 0 && gaps == overruns,
        );
        syst.disable_interrupt();
    }

    #[entry]
    fn main() -> ! {
        let mut cp = cortex_m::Peripherals::take().unwrap();
        hprintln!("qemu-selftest on mps2-an386");
        dsp_tests();
        queue_tests(&mut cp.SYST);
        let failed = FAILED.load(Ordering::Relaxed);
        hprintln!(
            "qemu-selftest: {} passed, {} failed",
            PASSED.load(Ordering::Relaxed),
            failed
        );
        board::exit(failed == 0)
    }
}
