//! The device core: everything the main loop does with a sample and a received byte, independent
//! of the board. It takes raw conversions from the acquisition queue, runs the offset cut and the
//! filters, batches samples into protocol frames, encodes them into the transmit buffer (dropping
//! and counting whole frames when the link is behind), and decodes and applies commands at frame
//! boundaries. The board supplies a [`BoardControl`] for the two things that touch hardware: the trim
//! DAC and the ADC's data rate.

pub mod command;
pub mod config;

use heapless::Deque;
use protocol::{
    encode, Accumulator, FilterConfig, Info, Malformed, Message, Outcome, Reply, Request, Sample,
    Status, CODE_MAX, CODE_MIN, MAX_FRAME, PROTOCOL_VERSION,
};

use crate::ads131m04::Osr;
use crate::dsp::FilterBank;
use crate::offset::{AutoNull, DriftTracker, NullState, NullStep, Tare};
use crate::stream::{FrameBuilder, RawSample, TxBuffer};
pub use config::{DeviceConfig, FW_VERSION};

/// Transmit buffer size: six full sample frames (168 bytes each) of slack for a busy link.
pub const TX_BYTES: usize = 1024;
/// Requests waiting for the next frame boundary.
pub const PENDING_REQUESTS: usize = 4;
/// Replies waiting for room in the transmit buffer.
const PENDING_REPLIES: usize = 8;
/// Receive accumulator: the longest request (set calibration, 39-byte body) encodes to 45 bytes.
pub const RX_BYTES: usize = 64;

/// A hardware action failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum HardwareError {
    /// The trim DAC did not accept the write.
    Dac,
    /// The ADC did not accept the configuration.
    Adc,
}

/// What the core asks of the board.
pub trait BoardControl {
    /// Write the trim-DAC codes of the three bridges (MCP4728 channels A..=C). Channel D holds
    /// the analog mid-rail reference and must not be touched.
    fn set_trim(&mut self, codes: [u16; 3]) -> Result<(), HardwareError>;
    /// Reprogram the ADC's oversampling ratio (and the sample clock where the board paces it).
    fn set_osr(&mut self, osr: Osr) -> Result<(), HardwareError>;
}

/// Counters for tests and benches (not on the wire).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    pub frames_queued: u32,
    pub frames_dropped: u32,
    /// Received frames that were not requests (bad CRC, overflow, malformed, wrong type).
    pub rx_errors: u32,
    /// Replies lost because PENDING_REPLIES were already waiting for a stalled link (the host
    /// times out and retries).
    pub replies_dropped: u32,
}

/// The device core.
pub struct Device {
    cfg: DeviceConfig,
    osr: Osr,
    batch: u8,
    filter_config: FilterConfig,
    calibration: protocol::Calibration,
    filters: FilterBank,
    tare: Tare,
    drift: DriftTracker,
    null: AutoNull,
    /// Trim-DAC codes in force, channels A..=C.
    dac: [u16; 3],
    /// An auto-null search or a tare is taking samples: the per-sample path visits them only
    /// then, and otherwise just subtracts the tare offset.
    offset_settling: bool,
    streaming: bool,
    epoch: u8,
    seq: u32,
    /// The open sample frame (empty between frames).
    frame: FrameBuilder,
    /// Status accumulated over the open frame.
    saturated: u8,
    overrun: bool,
    adc_error: bool,
    /// Frames dropped since the last frame that made it into the transmit buffer.
    dropped: u16,
    period_ns: u64,
    /// Device time of conversion `base_index`; a later conversion's time is this plus a period per
    /// index step, worked out only when needed (frame open, rate change) so the per-sample path
    /// does no 64-bit arithmetic.
    base_ns: u64,
    base_index: u32,
    last_index: Option<u32>,
    pending: Deque<Request, PENDING_REQUESTS>,
    replies: Deque<Reply, PENDING_REPLIES>,
    info_due: bool,
    rx: Accumulator<RX_BYTES>,
    tx: TxBuffer<TX_BYTES>,
    counters: Counters,
}

impl Device {
    /// The core at power-up. Call [`Self::power_up`] once the hardware is ready.
    pub fn new(cfg: DeviceConfig) -> Self {
        let mut dev = Self {
            osr: cfg.osr,
            batch: cfg.batch.clamp(1, protocol::MAX_BATCH as u8),
            filter_config: FilterConfig::NONE,
            calibration: cfg.calibration,
            filters: FilterBank::NONE,
            tare: Tare::new(),
            drift: DriftTracker::new(cfg.drift),
            null: AutoNull::new(cfg.null_timing, cfg.dac_initial),
            dac: cfg.dac_initial,
            offset_settling: false,
            streaming: false,
            epoch: 0,
            seq: 0,
            frame: FrameBuilder::new(),
            saturated: 0,
            overrun: false,
            adc_error: false,
            dropped: 0,
            period_ns: 0,
            base_ns: 0,
            base_index: 0,
            last_index: None,
            pending: Deque::new(),
            replies: Deque::new(),
            info_due: false,
            rx: Accumulator::with_capacity(),
            tx: TxBuffer::new(),
            counters: Counters::default(),
            cfg,
        };
        dev.period_ns = dev.period_ns_for(dev.osr);
        // A power-up filter that does not fit the rate leaves the filters off (visible in info).
        if let Ok(filters) = FilterBank::build(&cfg.filter, dev.rate_hz() as f32) {
            dev.filters = filters;
            dev.filter_config = cfg.filter;
        }
        dev
    }

    /// Write the initial DAC codes and, if configured, start the power-up auto-null.
    pub fn power_up(&mut self, hw: &mut impl BoardControl) -> Result<(), HardwareError> {
        // A lone delimiter first, so the host's first frame is clean (SPEC: receiving).
        self.tx.push_frame(&[0]);
        hw.set_trim(self.dac)?;
        if self.cfg.null_at_power_up {
            self.start_null(hw)?;
        }
        Ok(())
    }

    /// Output data rate in samples per second.
    pub fn rate_hz(&self) -> u32 {
        self.osr.data_rate_hz(self.cfg.clkin_hz)
    }

    pub fn osr(&self) -> Osr {
        self.osr
    }

    pub fn counters(&self) -> Counters {
        self.counters
    }

    pub fn streaming(&self) -> bool {
        self.streaming
    }

    pub fn config_epoch(&self) -> u8 {
        self.epoch
    }

    pub fn null_state(&self) -> NullState {
        self.null.state()
    }

    /// The transmit buffer; the board drains it into the port.
    pub fn tx(&mut self) -> &mut TxBuffer<TX_BYTES> {
        &mut self.tx
    }

    fn period_ns_for(&self, osr: Osr) -> u64 {
        1_000_000_000 / u64::from(osr.data_rate_hz(self.cfg.clkin_hz).max(1))
    }

    /// The acquisition interrupt dropped samples (queue full): flag it in the next frame.
    pub fn note_overruns(&mut self, count: u32) {
        if count > 0 {
            self.overrun = true;
        }
    }

    /// One conversion from the acquisition queue.
    pub fn on_sample(&mut self, raw: &RawSample, hw: &mut impl BoardControl) {
        // Device time follows the conversion index, so conversions lost before the queue still
        // advance it; the first conversion is t = 0.
        match self.last_index {
            Some(last) => {
                let steps = raw.index.wrapping_sub(last);
                if steps != 1 {
                    self.index_gap(steps);
                }
            }
            None => self.base_index = raw.index,
        }
        self.last_index = Some(raw.index);
        self.adc_error |= raw.read_error;
        for (ch, &code) in raw.codes.iter().enumerate() {
            if code >= CODE_MAX || code <= CODE_MIN {
                self.saturated |= 1 << ch;
            }
        }
        let sample = self.process([raw.codes[0], raw.codes[1], raw.codes[2]], hw);
        if self.streaming {
            self.add_to_frame(sample, raw.codes[3]);
        }
        if self.frame.is_empty() {
            // Between frames (every sample while not streaming): keep the index span short.
            self.fold_time();
            self.apply_pending(hw);
        }
    }

    /// Conversions were lost before the queue (`steps` > 1: flagged as an overrun), or an index
    /// repeated (`steps` = 0), which still counts one period as every conversion does.
    #[cold]
    fn index_gap(&mut self, steps: u32) {
        if steps == 0 {
            self.base_index = self.base_index.wrapping_sub(1);
        } else {
            self.overrun = true;
        }
    }

    /// Device time of the latest conversion, ns.
    fn time_ns(&self) -> u64 {
        let last = self.last_index.unwrap_or(self.base_index);
        self.base_ns + self.period_ns * u64::from(last.wrapping_sub(self.base_index))
    }

    /// Make the latest conversion the time base (before the period changes, and often enough
    /// that the index span never wraps).
    pub(crate) fn fold_time(&mut self) {
        if let Some(last) = self.last_index {
            self.base_ns = self.time_ns();
            self.base_index = last;
        }
    }

    /// Offset cut (null search, tare, drift) and filters for one sample of the three bridges.
    #[inline]
    fn process(&mut self, bridge: [i32; 3], hw: &mut impl BoardControl) -> Sample {
        if self.offset_settling {
            self.settle_offset(bridge, hw);
        }
        let offset = self.tare.offset();
        let tared: [i32; 3] = core::array::from_fn(|ch| bridge[ch].saturating_sub(offset[ch]));
        let corrected = self.drift.apply(tared);
        Sample {
            ch: self.filters.step_codes(corrected),
        }
    }

    /// One sample for a running null search or tare.
    fn settle_offset(&mut self, bridge: [i32; 3], hw: &mut impl BoardControl) {
        match self.null.on_sample(bridge) {
            NullStep::Continue => {}
            NullStep::SetDac(codes) => self.write_null_codes(codes, hw),
            NullStep::Done(codes) => {
                self.write_null_codes(codes, hw);
                // The tare was taken against the old trim: it no longer applies.
                self.tare.clear();
                self.reset_filters();
                self.epoch = self.epoch.wrapping_add(1);
            }
        }
        if self.tare.on_sample(bridge) {
            self.reset_filters();
            self.epoch = self.epoch.wrapping_add(1);
        }
        self.update_offset_settling();
    }

    /// Call whenever a null search or a tare starts or ends.
    pub(crate) fn update_offset_settling(&mut self) {
        self.offset_settling = self.null.state() == NullState::Searching || self.tare.collecting();
    }

    fn write_null_codes(&mut self, codes: [u16; 3], hw: &mut impl BoardControl) {
        self.dac = codes;
        if hw.set_trim(self.dac).is_err() {
            self.null.fail();
        }
    }

    /// Begin a search. If the DAC refuses the first write the state becomes Failed (reported) and
    /// the codes in force stay as they were.
    fn start_null(&mut self, hw: &mut impl BoardControl) -> Result<(), HardwareError> {
        let codes = self.null.start();
        let written = hw.set_trim(codes);
        if written.is_err() {
            self.null.fail();
        }
        self.update_offset_settling();
        written?;
        self.dac = codes;
        self.epoch = self.epoch.wrapping_add(1);
        Ok(())
    }

    fn reset_filters(&mut self) {
        self.filters.reset();
    }

    fn add_to_frame(&mut self, sample: Sample, temp: i32) {
        if self.frame.is_empty() {
            // The time stamp is only needed when a frame opens: the 64-bit division stays off
            // the per-sample path.
            self.frame.open((self.time_ns() / 1000) as u32, temp);
        }
        self.frame.push(sample.ch);
        if self.frame.len() >= usize::from(self.batch) {
            self.close_frame();
        }
    }

    /// Finish the open frame: sequence and status, encode, queue it whole or drop it whole.
    fn close_frame(&mut self) {
        let status = Status {
            saturated: self.saturated,
            null_state: self.null.state(),
            tare_active: self.tare.active(),
            drift_tracking: self.drift.enabled(),
            sample_overrun: self.overrun,
            adc_error: self.adc_error,
            config_epoch: self.epoch,
            dropped: self.dropped,
        };
        let queued = self.frame.finish_into(self.seq, &status, &mut self.tx);
        self.seq = self.seq.wrapping_add(1);
        self.saturated = 0;
        if queued {
            self.dropped = 0;
            self.overrun = false;
            self.adc_error = false;
            self.counters.frames_queued += 1;
        } else {
            // The flags are kept for the next frame that gets through; the count saturates.
            self.dropped = self.dropped.saturating_add(1);
            self.counters.frames_dropped += 1;
        }
    }

    /// Bytes received from the host. Each complete request is queued for the next frame
    /// boundary, or nacked at once (busy, malformed), however many one call delivers.
    pub fn on_rx(&mut self, bytes: &[u8]) {
        for outcome in self.rx.feed(bytes) {
            let nack = match outcome {
                Outcome::Message(Message::Request(req)) => match self.pending.push_back(req) {
                    Ok(()) => continue,
                    Err(req) => command::nack(&req, protocol::NackCode::Busy),
                },
                Outcome::Malformed(Malformed::BadRequest { tag, opcode, code }) => {
                    Reply::Nack { tag, opcode, code }
                }
                _ => {
                    self.counters.rx_errors += 1;
                    continue;
                }
            };
            // The accumulator holds `self.rx`: queue through the fields, not `self.reply`.
            queue_reply(&mut self.replies, &mut self.tx, &mut self.counters, nack);
        }
        self.flush_replies();
    }

    /// Call from the main loop when idle: applies waiting commands if no frame is open (e.g. while
    /// stopped, or when no samples arrive) and retries replies that did not fit the buffer.
    pub fn poll(&mut self, hw: &mut impl BoardControl) {
        if self.frame.is_empty() {
            self.apply_pending(hw);
        }
        self.flush_replies();
    }

    #[inline]
    fn apply_pending(&mut self, hw: &mut impl BoardControl) {
        if self.pending.is_empty() && self.replies.is_empty() && !self.info_due {
            return;
        }
        while let Some(req) = self.pending.pop_front() {
            let reply = self.apply(&req, hw);
            self.reply(reply);
        }
        self.flush_replies();
    }

    fn reply(&mut self, reply: Reply) {
        queue_reply(&mut self.replies, &mut self.tx, &mut self.counters, reply);
        self.flush_replies();
    }

    /// Move waiting replies (and an info frame after its ack) into the transmit buffer.
    fn flush_replies(&mut self) {
        // Cheap exit on the per-frame path: nothing waiting, no encode buffer to clear.
        if self.replies.is_empty() && !self.info_due {
            return;
        }
        if !flush_reply_queue(&mut self.replies, &mut self.tx) {
            return;
        }
        if self.info_due {
            let mut wire = [0u8; MAX_FRAME];
            let n = encode(&Message::Info(self.info()), &mut wire).unwrap_or(0);
            if self.tx.push_frame(&wire[..n]) {
                self.info_due = false;
            }
        }
    }

    /// The info frame for the current state.
    pub fn info(&self) -> Info {
        let offset = self.tare.offset();
        Info {
            protocol_version: PROTOCOL_VERSION,
            fw_version: FW_VERSION,
            chip_serial: self.cfg.chip_serial,
            sample_rate_hz: self.rate_hz(),
            batch: self.batch,
            pga_gain: self.cfg.pga.map(|p| p.gain()),
            vref_mv: self.cfg.vref_mv,
            amp_gain: self.cfg.amp_gain,
            excitation_v: self.cfg.excitation_v,
            filter: self.filter_config,
            calibration: self.calibration,
            dac_codes: [
                self.dac[0],
                self.dac[1],
                self.dac[2],
                self.cfg.dac_vmid_code,
            ],
            tare: offset,
            drift: self.drift.correction(),
            null_state: self.null.state(),
            drift_tracking: self.drift.enabled(),
            streaming: self.streaming,
            config_epoch: self.epoch,
        }
    }
}

/// Queue `reply` behind the waiting ones, making room by moving those into the transmit buffer
/// first; with PENDING_REPLIES still waiting (a stalled link) the reply is dropped and counted.
fn queue_reply(
    replies: &mut Deque<Reply, PENDING_REPLIES>,
    tx: &mut TxBuffer<TX_BYTES>,
    counters: &mut Counters,
    reply: Reply,
) {
    if replies.is_full() {
        flush_reply_queue(replies, tx);
    }
    if replies.push_back(reply).is_err() {
        counters.replies_dropped += 1;
    }
}

/// Move waiting replies into the transmit buffer in order; false if some still wait for room.
fn flush_reply_queue(
    replies: &mut Deque<Reply, PENDING_REPLIES>,
    tx: &mut TxBuffer<TX_BYTES>,
) -> bool {
    let mut wire = [0u8; MAX_FRAME];
    while let Some(reply) = replies.front().copied() {
        let n = encode(&Message::Reply(reply), &mut wire).unwrap_or(0);
        if !tx.push_frame(&wire[..n]) {
            return false;
        }
        replies.pop_front();
    }
    true
}

#[cfg(test)]
mod tests;
