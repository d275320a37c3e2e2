//! Command handling: every request is checked and applied at a frame boundary and answered with
//! an ack, a nack carrying the reason, or a pong. A refused request changes nothing.
//!
//! Rules beyond the protocol's argument checks:
//! - set rate: one of the ADC's exact rates at the board's clock, and the running low-pass must
//!   remain valid at the new rate (else out of range: set the filter first);
//! - set filter: alpha in (0, 1]; order 0, 2 or 4; cut-off in [1e-3·rate, 0.45·rate) (the lower
//!   bound is this firmware's f32 accuracy limit, see dsp::butterworth);
//! - tare: 1..=65535 samples; busy while an auto-null search or another tare runs;
//! - auto-null: busy while a search runs; a DAC that refuses the write is a hardware nack;
//! - set batch: 1..=16.
//!
//! Every accepted change of configuration increments `config_epoch`; tare and auto-null increment
//! it again when they take effect.

use protocol::{Command, NackCode, Reply, Request, MAX_BATCH};

use super::{BoardControl, Device};
use crate::ads131m04::Osr;
use crate::dsp::FilterBank;
use crate::offset::NullState;

/// A nack for `req`.
pub fn nack(req: &Request, code: NackCode) -> Reply {
    Reply::Nack {
        tag: req.tag,
        opcode: req.command.opcode(),
        code,
    }
}

impl Device {
    /// Apply one request; the reply says whether it was.
    pub fn apply(&mut self, req: &Request, hw: &mut impl BoardControl) -> Reply {
        match self.execute(&req.command, hw) {
            Ok(Some(reply)) => reply_with_tag(reply, req.tag),
            Ok(None) => Reply::Ack {
                tag: req.tag,
                opcode: req.command.opcode(),
            },
            Err(code) => nack(req, code),
        }
    }

    /// Ok(None) = ack; Ok(Some(reply)) = a different positive answer (pong).
    fn execute(
        &mut self,
        command: &Command,
        hw: &mut impl BoardControl,
    ) -> Result<Option<Reply>, NackCode> {
        match *command {
            Command::Start => self.streaming = true,
            Command::Stop => self.streaming = false,
            Command::SetRate { hz } => self.set_rate(hz, hw)?,
            Command::SetFilter(config) => {
                self.filters = FilterBank::build(&config, self.rate_hz() as f32)
                    .map_err(|_| NackCode::OutOfRange)?;
                self.filter_config = config;
                self.bump();
            }
            Command::Tare { samples } => {
                if samples == 0 {
                    return Err(NackCode::OutOfRange);
                }
                if self.null.state() == NullState::Searching || self.tare.collecting() {
                    return Err(NackCode::Busy);
                }
                self.tare.start(samples);
                self.update_offset_settling();
            }
            Command::ClearTare => {
                self.tare.clear();
                self.update_offset_settling();
                self.reset_filters();
                self.bump();
            }
            Command::AutoNull => {
                if self.null.state() == NullState::Searching {
                    return Err(NackCode::Busy);
                }
                self.start_null(hw).map_err(|_| NackCode::Hardware)?;
            }
            Command::GetInfo => self.info_due = true,
            Command::SetCalibration(matrix) => {
                // Finite values are guaranteed by the decoder.
                self.calibration = matrix;
                self.bump();
            }
            Command::Ping { nonce } => return Ok(Some(Reply::Pong { tag: 0, nonce })),
            Command::SetDriftTracking { enabled } => {
                self.drift.set_enabled(enabled);
                self.bump();
            }
            Command::SetBatch { samples } => {
                if samples == 0 || usize::from(samples) > MAX_BATCH {
                    return Err(NackCode::OutOfRange);
                }
                self.batch = samples;
                self.bump();
            }
            _ => return Err(NackCode::UnknownCommand),
        }
        Ok(None)
    }

    fn set_rate(&mut self, hz: u32, hw: &mut impl BoardControl) -> Result<(), NackCode> {
        let osr = Osr::for_rate(hz, self.cfg.clkin_hz).ok_or(NackCode::OutOfRange)?;
        let filters =
            FilterBank::build(&self.filter_config, hz as f32).map_err(|_| NackCode::OutOfRange)?;
        hw.set_osr(osr).map_err(|_| NackCode::Hardware)?;
        self.osr = osr;
        self.fold_time();
        self.period_ns = self.period_ns_for(osr);
        self.filters = filters;
        self.bump();
        Ok(())
    }

    fn bump(&mut self) {
        self.epoch = self.epoch.wrapping_add(1);
    }
}

fn reply_with_tag(reply: Reply, tag: u8) -> Reply {
    match reply {
        Reply::Pong { nonce, .. } => Reply::Pong { tag, nonce },
        Reply::Ack { opcode, .. } => Reply::Ack { tag, opcode },
        Reply::Nack { opcode, code, .. } => Reply::Nack { tag, opcode, code },
    }
}
