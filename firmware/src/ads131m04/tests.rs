//! The driver against embedded-hal-mock transactions (every error path) and against the sim's
//! register-level emulation.

use super::*;
use ads131m04_regs::crc::{crc16_bitwise, SEED};
use embedded_hal::spi::{ErrorKind, ErrorType, Operation};
use embedded_hal_mock::eh1::digital::{Mock as PinMock, State, Transaction as PinTx};
use embedded_hal_mock::eh1::spi::{Mock as SpiMock, Transaction as SpiTx};
use embedded_hal_mock::eh1::MockError;

/// Bytes the driver sends: 16-bit words MSB-aligned in `wb`-byte words, optional input CRC after
/// them, padded to six words.
fn tx(wb: usize, words: &[u16], with_crc: bool) -> Vec<u8> {
    let mut out = vec![0u8; 6 * wb];
    for (i, w) in words.iter().enumerate() {
        out[i * wb..i * wb + 2].copy_from_slice(&w.to_be_bytes());
    }
    if with_crc {
        let at = words.len() * wb;
        let crc = crc16_bitwise(SEED, &out[..at]);
        out[at..at + 2].copy_from_slice(&crc.to_be_bytes());
    }
    out
}

/// Bytes the device answers: response word, four 24-bit codes in `wb`-byte words, CRC.
fn rx(wb: usize, response: u16, codes: [i32; 4]) -> Vec<u8> {
    let mut out = vec![0u8; 6 * wb];
    out[..2].copy_from_slice(&response.to_be_bytes());
    for (ch, code) in codes.iter().enumerate() {
        let be = code.to_be_bytes();
        let at = (ch + 1) * wb;
        match wb {
            2 => out[at..at + 2].copy_from_slice(&be[1..3]),
            3 => out[at..at + 3].copy_from_slice(&be[1..4]),
            _ => out[at..at + 4].copy_from_slice(&be),
        }
    }
    let crc = crc16_bitwise(SEED, &out[..5 * wb]);
    out[5 * wb..5 * wb + 2].copy_from_slice(&crc.to_be_bytes());
    out
}

fn frame(tx: Vec<u8>, rx: Vec<u8>) -> [SpiTx<u8>; 3] {
    [
        SpiTx::transaction_start(),
        SpiTx::transfer(tx, rx),
        SpiTx::transaction_end(),
    ]
}

fn frames(list: Vec<(Vec<u8>, Vec<u8>)>) -> Vec<SpiTx<u8>> {
    list.into_iter().flat_map(|(t, r)| frame(t, r)).collect()
}

const STATUS_24: u16 = 0x0500;

fn config() -> Config {
    Config {
        word_length: WordLength::Bits32SignExtend,
        osr: Osr::Osr4096,
        gains: [
            Pga::X1,
            Pga::from_gain(2).unwrap(),
            Pga::from_gain(4).unwrap(),
            Pga::X1,
        ],
        input_crc: true,
    }
}

/// The frames of a successful `init(&config())`.
fn init_frames() -> Vec<(Vec<u8>, Vec<u8>)> {
    let z = [0; 4];
    let mode = 0x1310; // RX_CRC_EN | WLENGTH=11 | TIMEOUT
    vec![
        (tx(3, &[cmd::RESET], false), rx(3, STATUS_24, z)),
        (tx(3, &[cmd::NULL], false), rx(3, cmd::RESET_ACK, z)),
        (tx(3, &[cmd::rreg(addr::ID)], false), rx(3, STATUS_24, z)),
        (tx(3, &[cmd::NULL], false), rx(3, 0x2400, z)),
        (
            tx(3, &[cmd::wreg(addr::MODE, 1), mode], false),
            rx(3, STATUS_24, z),
        ),
        (
            tx(4, &[cmd::NULL], true),
            rx(4, cmd::wreg_ack(addr::MODE, 1), z),
        ),
        (
            tx(4, &[cmd::wreg(addr::CLOCK, 1), 0x0F16], true),
            rx(4, 0x0300, z),
        ),
        (
            tx(4, &[cmd::NULL], true),
            rx(4, cmd::wreg_ack(addr::CLOCK, 1), z),
        ),
        (
            tx(4, &[cmd::wreg(addr::GAIN1, 1), 0x0210], true),
            rx(4, 0x0300, z),
        ),
        (
            tx(4, &[cmd::NULL], true),
            rx(4, cmd::wreg_ack(addr::GAIN1, 1), z),
        ),
    ]
}

#[test]
fn init_resets_checks_id_and_configures() {
    let mut spi = SpiMock::new(&frames(init_frames()));
    let mut pin = PinMock::new(&[]);
    let mut adc = Ads131m04::new(spi.clone(), pin.clone());
    assert_eq!(adc.init(&config()), Ok(0x2400));
    spi.done();
    pin.done();
}

#[test]
fn read_decodes_status_and_codes_in_32_bit_mode() {
    let mut list = init_frames();
    list.push((
        tx(4, &[cmd::NULL], true),
        rx(4, 0x030F, [1, -1, 8_388_607, -8_388_608]),
    ));
    let mut spi = SpiMock::new(&frames(list));
    let mut adc = Ads131m04::new(spi.clone(), PinMock::new(&[]));
    adc.init(&config()).unwrap();
    let conv = adc.read().unwrap();
    assert_eq!(conv.codes, [1, -1, 8_388_607, -8_388_608]);
    assert!(conv.status.drdy(0) && conv.status.drdy(3) && !conv.status.reset());
    let (_, mut pin) = adc.release();
    spi.done();
    pin.done();
}

#[test]
fn wrong_id_is_refused() {
    let mut list = init_frames();
    list.truncate(4);
    list[3].1 = rx(3, 0x2200, [0; 4]); // a two-channel ADS131M02
    let mut spi = SpiMock::new(&frames(list));
    let mut adc = Ads131m04::new(spi.clone(), PinMock::new(&[]));
    assert_eq!(adc.init(&config()), Err(Error::WrongId(0x2200)));
    let (_, mut pin) = adc.release();
    spi.done();
    pin.done();
}

#[test]
fn bad_crc_on_a_data_frame_is_an_error() {
    let mut bad = rx(3, 0x050F, [5, 6, 7, 8]);
    bad[7] ^= 0x40; // one bit of channel 1 flipped on the wire, CRC word untouched
    let computed = crc16_bitwise(SEED, &bad[..15]);
    let received = u16::from_be_bytes([bad[15], bad[16]]);
    let mut spi = SpiMock::new(&frames(vec![(tx(3, &[cmd::NULL], false), bad)]));
    let mut adc = Ads131m04::new(spi.clone(), PinMock::new(&[]));
    assert_eq!(adc.read(), Err(Error::Crc { computed, received }));
    let (_, mut pin) = adc.release();
    spi.done();
    pin.done();
}

#[test]
fn device_reported_input_crc_error_surfaces() {
    let mut spi = SpiMock::new(&frames(vec![(
        tx(3, &[cmd::NULL], false),
        rx(3, 0x1500, [0; 4]),
    )]));
    let mut adc = Ads131m04::new(spi.clone(), PinMock::new(&[]));
    assert_eq!(adc.read(), Err(Error::InputCrc));
    let (_, mut pin) = adc.release();
    spi.done();
    pin.done();
}

#[test]
fn unexpected_acknowledgement_is_an_error() {
    let z = [0; 4];
    let list = vec![
        (
            tx(3, &[cmd::wreg(addr::GAIN1, 1), 0x0001], false),
            rx(3, STATUS_24, z),
        ),
        (tx(3, &[cmd::NULL], false), rx(3, STATUS_24, z)), // the write was not acknowledged
    ];
    let mut spi = SpiMock::new(&frames(list));
    let mut adc = Ads131m04::new(spi.clone(), PinMock::new(&[]));
    assert_eq!(
        adc.write_register(addr::GAIN1, 1),
        Err(Error::Response {
            expected: cmd::wreg_ack(addr::GAIN1, 1),
            received: STATUS_24
        })
    );
    let (_, mut pin) = adc.release();
    spi.done();
    pin.done();
}

/// A bus whose every transaction fails.
struct BrokenBus;
impl ErrorType for BrokenBus {
    type Error = ErrorKind;
}
impl SpiDevice for BrokenBus {
    fn transaction(
        &mut self,
        _ops: &mut [Operation<'_, u8>],
    ) -> core::result::Result<(), ErrorKind> {
        Err(ErrorKind::ModeFault)
    }
}

#[test]
fn bus_error_is_kept() {
    let mut adc = Ads131m04::new(BrokenBus, PinMock::new(&[]));
    assert_eq!(adc.read(), Err(Error::Spi(ErrorKind::ModeFault)));
    assert_eq!(adc.init(&config()), Err(Error::Spi(ErrorKind::ModeFault)));
    adc.release().1.done();
}

#[test]
fn drdy_level_and_pin_error() {
    let err = MockError::Io(std::io::ErrorKind::NotConnected);
    let pin = PinMock::new(&[
        PinTx::get(State::Low),
        PinTx::get(State::High),
        PinTx::get(State::Low).with_error(err.clone()),
    ]);
    let mut spi = SpiMock::new(&[]);
    let mut adc = Ads131m04::new(spi.clone(), pin);
    assert_eq!(adc.data_ready(), Ok(true));
    assert_eq!(adc.data_ready(), Ok(false));
    assert_eq!(adc.data_ready(), Err(Error::Drdy(err)));
    let (_, mut pin) = adc.release();
    spi.done();
    pin.done();
}

#[test]
fn simple_commands_expect_their_echo() {
    let z = [0; 4];
    let mut list = Vec::new();
    for c in [cmd::STANDBY, cmd::WAKEUP, cmd::LOCK, cmd::UNLOCK] {
        list.push((tx(3, &[c], false), rx(3, STATUS_24, z)));
        list.push((tx(3, &[cmd::NULL], false), rx(3, c, z)));
    }
    let mut spi = SpiMock::new(&frames(list));
    let mut adc = Ads131m04::new(spi.clone(), PinMock::new(&[]));
    adc.standby().unwrap();
    adc.wakeup().unwrap();
    adc.lock().unwrap();
    adc.unlock().unwrap();
    let (_, mut pin) = adc.release();
    spi.done();
    pin.done();
}

mod against_emulation {
    use super::super::*;
    use crate::params::EMULATED_ADC;
    use ads131m04_regs::addr;
    use core::cell::RefCell;
    use protocol::codes::volts_to_code;
    use sim::ads131m04::stimulus::{Stimulus, StimulusParams};
    use sim::ads131m04::{handles, Ads131m04 as Emu};

    fn chip() -> RefCell<Emu<Stimulus>> {
        RefCell::new(Emu::new(
            Stimulus::new(StimulusParams::QEMU_BOARD),
            EMULATED_ADC,
        ))
    }

    #[test]
    fn every_word_length_with_and_without_input_crc_reads_the_ideal_codes() {
        let reference = Stimulus::new(StimulusParams::QEMU_BOARD);
        for word_length in [
            WordLength::Bits16,
            WordLength::Bits24,
            WordLength::Bits32ZeroPad,
            WordLength::Bits32SignExtend,
        ] {
            for input_crc in [false, true] {
                let chip = chip();
                let (spi, drdy) = handles(&chip);
                let mut adc = Ads131m04::new(spi, drdy);
                let gains = [
                    Pga::X1,
                    Pga::from_gain(2).unwrap(),
                    Pga::X1,
                    Pga::from_gain(8).unwrap(),
                ];
                let config = Config {
                    word_length,
                    osr: Osr::Osr2048,
                    gains,
                    input_crc,
                };
                assert_eq!(adc.init(&config).unwrap() & 0xFF00, 0x2400);
                assert_eq!(chip.borrow().data_rate_hz(), 2000.0);
                for _ in 0..20 {
                    assert!(!adc.data_ready().unwrap());
                    chip.borrow_mut().convert();
                    assert!(adc.data_ready().unwrap());
                    let n = chip.borrow().conversions() - 1;
                    let conv = adc.read().unwrap();
                    assert_eq!(conv.status.0 & 0xF, 0xF);
                    let v = reference.volts(n);
                    for ch in 0..4 {
                        let gain = u32::from(gains[ch].gain());
                        let mut expect = volts_to_code(f64::from(v[ch]), EMULATED_ADC.vref_v, gain);
                        if word_length == WordLength::Bits16 {
                            expect = (expect >> 8) << 8;
                        }
                        assert_eq!(
                            conv.codes[ch], expect,
                            "{word_length:?} crc {input_crc} ch {ch} n {n}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn registers_read_back_what_was_written() {
        let chip = chip();
        let (spi, drdy) = handles(&chip);
        let mut adc = Ads131m04::new(spi, drdy);
        let config = Config {
            word_length: WordLength::Bits24,
            osr: Osr::Osr128,
            gains: [Pga::X1; 4],
            input_crc: true,
        };
        adc.init(&config).unwrap();
        adc.set_gains([Pga::from_gain(128).unwrap(); 4]).unwrap();
        assert_eq!(adc.read_register(addr::GAIN1).unwrap(), 0x7777);
        assert_eq!(chip.borrow().register(addr::GAIN1), 0x7777);
        adc.lock().unwrap();
        assert!(matches!(
            adc.set_osr(Osr::Osr256),
            Err(Error::Response { .. })
        ));
        adc.unlock().unwrap();
        adc.set_osr(Osr::Osr256).unwrap();
        assert_eq!(chip.borrow().data_rate_hz(), 16_000.0);
    }
}
