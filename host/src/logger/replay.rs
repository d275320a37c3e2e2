//! Re-decoding a capture into a recording CSV through the same decoder, tracker and recorder
//! as live logging: an MCAP file written by `tactile log` (complete, or recovered after a
//! crash) or a raw byte capture of the serial line.

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use protocol::{Info, Message, Outcome};

use super::cdr;
use super::mcap_io::{recover_bytes, StoredMessage, MCAP_MAGIC, RAW_ENCODING};
use super::{FileError, Recorder, Setup};
use crate::decode::FastDecoder;
use crate::device::{Event, Frame, Gap, GapKind, Step, Tracker};

/// What a replay found.
#[derive(Debug, Default, Clone)]
pub struct ReplaySummary {
    pub frames: u64,
    pub rows: u64,
    pub crc_errors: u64,
    pub malformed: u64,
    pub overflows: u64,
    pub gaps: u64,
    /// Why the input ended early (an MCAP whose writer was killed), if it did.
    pub truncated: Option<String>,
}

/// Where the replayed CSV goes.
enum Output<'a> {
    File(&'a Path),
    Stdout,
    Writer(Box<dyn std::io::Write>),
}

/// Turns decoded frames into recorder events.
struct Replayer<'a> {
    /// Taken when the recorder is created, at the first sample frame.
    out: Option<Output<'a>>,
    setup: &'a Setup,
    info: Option<Info>,
    rec: Option<Recorder>,
    tracker: Tracker,
    summary: ReplaySummary,
    error: Option<FileError>,
    input: PathBuf,
}

impl Replayer<'_> {
    fn on_outcome(&mut self, outcome: Outcome, raw: &[u8], host_time: Option<SystemTime>) {
        if self.error.is_some() {
            return;
        }
        let r = match outcome {
            Outcome::Message(Message::Info(i)) => {
                let ev = Event::Info(i.clone());
                self.info = Some(i);
                self.rec.as_mut().map_or(Ok(()), |r| r.on_event(&ev))
            }
            Outcome::Message(Message::Sample(f)) => self.on_sample(f, raw, host_time),
            Outcome::Message(_) => Ok(()),
            Outcome::CrcError => {
                self.summary.crc_errors += 1;
                Ok(())
            }
            Outcome::Malformed(_) => {
                self.summary.malformed += 1;
                Ok(())
            }
            Outcome::Overflow => {
                self.summary.overflows += 1;
                Ok(())
            }
        };
        if let Err(e) = r {
            self.error = Some(e);
        }
    }

    fn on_sample(
        &mut self,
        f: protocol::SampleFrame,
        raw: &[u8],
        host_time: Option<SystemTime>,
    ) -> Result<(), FileError> {
        let Step::Keep {
            gap,
            t_device_us,
            session,
        } = self.tracker.step(f.seq, f.t_us, f.status.dropped)
        else {
            return Ok(());
        };
        // A raw capture has no host clock: the device clock stands in for it.
        let host_time = host_time.unwrap_or(UNIX_EPOCH + Duration::from_micros(t_device_us));
        if self.rec.is_none() {
            let info = self.info.as_ref().ok_or_else(|| FileError::Capture {
                path: self.input.clone(),
                why: "no info frame before the first sample frame: cannot convert codes to volts"
                    .into(),
            })?;
            let rec = match self.out.take() {
                Some(Output::File(path)) => Recorder::create(path, info, self.setup, host_time),
                Some(Output::Writer(w)) => {
                    Recorder::create_on(w, &self.input, info, self.setup, host_time)
                }
                Some(Output::Stdout) | None => Recorder::create_on(
                    Box::new(std::io::stdout()),
                    Path::new("stdout"),
                    info,
                    self.setup,
                    host_time,
                ),
            };
            self.rec = Some(rec?);
        }
        let rec = self.rec.as_mut().expect("created above");
        if let Some(kind) = gap {
            self.summary.gaps += 1;
            rec.on_event(&Event::Gap(Gap {
                kind,
                host_time,
                session,
            }))?;
        }
        self.summary.frames += 1;
        let seq = f.seq;
        rec.on_event(&Event::Frame(Frame {
            seq,
            t_device_us,
            host_time,
            session,
            frame: f,
            raw: raw.to_vec(),
        }))
    }

    /// A gap message: CDR of [`cdr::GAP_SCHEMA`], or the JSON of files written before it.
    fn on_gap_message(
        &mut self,
        encoding: &str,
        data: &[u8],
        host_time: SystemTime,
    ) -> Result<(), FileError> {
        let bad = |why: String| FileError::Capture {
            path: self.input.clone(),
            why: format!("gap message: {why}"),
        };
        let (kind, missing) = if encoding == cdr::MESSAGE_ENCODING {
            let fields = cdr::parse_schema(cdr::GAP_SCHEMA).map_err(bad)?;
            let v = cdr::decode(&fields, data).map_err(bad)?;
            let get = |name: &str| v.iter().find(|(n, _)| n == name).map(|(_, v)| v.clone());
            let kind = match get("kind") {
                Some(cdr::Value::Text(k)) => k,
                _ => String::new(),
            };
            (kind, get("missing").map_or(-1.0, |m| m.num()))
        } else {
            let v: serde_json::Value =
                serde_json::from_slice(data).map_err(|e| bad(e.to_string()))?;
            let kind = v.get("kind").and_then(|k| k.as_str()).unwrap_or_default();
            let missing = v.get("missing").and_then(|m| m.as_f64()).unwrap_or(-1.0);
            (kind.to_string(), missing)
        };
        let missing = (missing >= 0.0).then_some(missing as u64);
        let kind = match kind.as_str() {
            "disconnected" => GapKind::Disconnected,
            "reconnected" => {
                self.tracker.new_session();
                GapKind::Reconnected {
                    downtime: Duration::ZERO,
                    missing,
                }
            }
            // Sequence gaps, restarts and queue drops are found again from the frames themselves.
            _ => return Ok(()),
        };
        self.summary.gaps += 1;
        let session = self.tracker.session();
        match self.rec.as_mut() {
            Some(r) => r.on_event(&Event::Gap(Gap {
                kind,
                host_time,
                session,
            })),
            None => Ok(()),
        }
    }
}

/// The largest MCAP file replayed: its messages are held in memory (a raw capture streams).
pub const MAX_MCAP_BYTES: u64 = 1 << 30;

/// Replay `input` into the CSV `out` (stdout if `None`). `sensor` picks one sensor of a
/// multi-sensor MCAP. A raw capture is streamed; an MCAP file over [`MAX_MCAP_BYTES`] is
/// refused.
pub fn replay(
    input: &Path,
    out: Option<&Path>,
    setup: &Setup,
    sensor: Option<&str>,
) -> Result<ReplaySummary, FileError> {
    use std::io::Read;
    let mut file = std::fs::File::open(input).map_err(|e| FileError::open(input, e))?;
    let mut head = Vec::with_capacity(MCAP_MAGIC.len());
    (&mut file)
        .take(MCAP_MAGIC.len() as u64)
        .read_to_end(&mut head)
        .map_err(|e| FileError::open(input, e))?;
    let mut r = Replayer::new(
        input,
        out.map(Output::File).unwrap_or(Output::Stdout),
        setup,
    );
    if head == MCAP_MAGIC {
        let len = file
            .metadata()
            .map_err(|e| FileError::open(input, e))?
            .len();
        if len > MAX_MCAP_BYTES {
            return Err(FileError::TooLarge {
                path: input.into(),
                bytes: len,
                limit_bytes: MAX_MCAP_BYTES,
                why: "an MCAP file is replayed in memory; a raw capture streams",
            });
        }
        let bytes = std::fs::read(input).map_err(|e| FileError::open(input, e))?;
        r.mcap(&bytes, sensor)?;
    } else {
        let mut decoder = FastDecoder::new();
        let mut chunk = vec![0u8; 64 * 1024];
        decoder.feed(&head, |j| r.on_outcome(j.outcome, j.raw, None));
        loop {
            let n = file
                .read(&mut chunk)
                .map_err(|e| FileError::open(input, e))?;
            if n == 0 || r.error.is_some() {
                break;
            }
            decoder.feed(&chunk[..n], |j| r.on_outcome(j.outcome, j.raw, None));
        }
    }
    r.finish()
}

/// [`replay`] of bytes already in memory (`name` stands for the file in messages) into `out`.
pub fn replay_bytes(
    bytes: &[u8],
    name: &Path,
    out: Box<dyn std::io::Write>,
    setup: &Setup,
    sensor: Option<&str>,
) -> Result<ReplaySummary, FileError> {
    let mut r = Replayer::new(name, Output::Writer(out), setup);
    if bytes.starts_with(MCAP_MAGIC) {
        r.mcap(bytes, sensor)?;
    } else {
        FastDecoder::new().feed(bytes, |j| r.on_outcome(j.outcome, j.raw, None));
    }
    r.finish()
}

impl<'a> Replayer<'a> {
    fn new(input: &Path, out: Output<'a>, setup: &'a Setup) -> Self {
        Replayer {
            out: Some(out),
            setup,
            info: None,
            rec: None,
            tracker: Tracker::default(),
            summary: ReplaySummary::default(),
            error: None,
            input: input.to_path_buf(),
        }
    }

    /// Feed the raw frames and gap marks of one sensor of an MCAP file.
    fn mcap(&mut self, bytes: &[u8], sensor: Option<&str>) -> Result<(), FileError> {
        let rec = recover_bytes(&self.input, bytes)?;
        self.summary.truncated = rec.truncated.clone();
        let topic = pick_topic(&self.input, &rec.messages, sensor)?;
        let base = topic.trim_end_matches("/raw").to_owned();
        let gap_topic = format!("{base}/gap");
        let mut decoder = FastDecoder::new();
        let mut framed = Vec::new();
        for m in &rec.messages {
            let t = UNIX_EPOCH + Duration::from_nanos(m.publish_ns);
            if *m.topic == *topic {
                framed.clear();
                framed.extend_from_slice(&m.data);
                framed.push(0);
                decoder.feed(&framed, |j| self.on_outcome(j.outcome, j.raw, Some(t)));
            } else if *m.topic == gap_topic {
                self.on_gap_message(&m.encoding, &m.data, t)?;
            }
        }
        Ok(())
    }

    /// The summary once the input is consumed, or why nothing could be replayed.
    fn finish(mut self) -> Result<ReplaySummary, FileError> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        let s = &self.summary;
        if self.info.is_none() && s.frames == 0 && s.crc_errors + s.malformed + s.overflows == 0 {
            return Err(FileError::Capture {
                path: self.input.clone(),
                why: "no frame found: not a tactile capture".into(),
            });
        }
        let mut rec = self.rec.take().ok_or_else(|| FileError::Capture {
            path: self.input.clone(),
            why: "no sample frame in the capture".into(),
        })?;
        rec.finish("replay")?;
        self.summary.rows = rec.rows;
        Ok(self.summary)
    }
}

fn pick_topic(
    input: &Path,
    messages: &[StoredMessage],
    sensor: Option<&str>,
) -> Result<String, FileError> {
    let mut topics: Vec<&str> = messages
        .iter()
        .filter(|m| &*m.encoding == RAW_ENCODING)
        .map(|m| &*m.topic)
        .collect();
    topics.dedup();
    topics.sort_unstable();
    topics.dedup();
    let chosen: Vec<&&str> = topics
        .iter()
        .filter(|t| sensor.is_none_or(|s| t.contains(s)))
        .collect();
    match chosen.as_slice() {
        [one] => Ok((**one).to_owned()),
        [] => Err(FileError::Capture {
            path: input.into(),
            why: "no raw tactile frames in this MCAP".into(),
        }),
        many => Err(FileError::Capture {
            path: input.into(),
            why: format!(
                "several sensors ({}); choose one with --sensor",
                many.iter().map(|t| **t).collect::<Vec<_>>().join(", ")
            ),
        }),
    }
}
