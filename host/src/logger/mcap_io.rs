//! The MCAP side of a recording: every received frame as raw wire bytes (re-decodable by
//! `tactile replay`), every sample decoded with its times (CDR messages of a `ros2msg` schema
//! declared in the file, [`super::cdr`]: plots directly in Foxglove), gaps and info frames.
//! Log times are the host time base of all fingers ([`crate::clock`]). Chunks are uncompressed and closed at every flush, so a
//! killed logger leaves complete chunks that [`recover`] reads back.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use mcap::records::MessageHeader;

use super::{cdr, FileError, FLUSH_EVERY};

/// Encoding label of the raw topic: COBS frames of protocol/SPEC.md without delimiter.
pub const RAW_ENCODING: &str = "tactile-cobs-v1";

/// Channel ids of one sensor.
#[derive(Debug, Clone, Copy)]
pub struct SensorChannels {
    pub raw: u16,
    pub sample: u16,
    pub gap: u16,
}

/// An MCAP file being written.
pub struct McapSink {
    path: PathBuf,
    w: mcap::Writer<BufWriter<File>>,
    sample_schema: u16,
    gap_schema: u16,
    seq: u32,
    last_flush: Instant,
}

impl McapSink {
    pub fn create(path: &Path) -> Result<Self, FileError> {
        let err = |e: mcap::McapError| FileError::Write {
            path: path.to_path_buf(),
            source: std::io::Error::other(e),
        };
        let file = File::create(path).map_err(|e| FileError::write(path, e))?;
        let opts = mcap::WriteOptions::new()
            .compression(None)
            .profile("")
            .library("tactile")
            // Chunks are assembled in memory and written whole: a kill leaves whole chunks.
            .disable_seeking(true);
        let mut w = opts.create(BufWriter::new(file)).map_err(err)?;
        let sample_schema = w
            .add_schema(
                cdr::SAMPLE_NAME,
                cdr::SCHEMA_ENCODING,
                cdr::SAMPLE_SCHEMA.as_bytes(),
            )
            .map_err(err)?;
        let gap_schema = w
            .add_schema(
                cdr::GAP_NAME,
                cdr::SCHEMA_ENCODING,
                cdr::GAP_SCHEMA.as_bytes(),
            )
            .map_err(err)?;
        Ok(Self {
            path: path.to_path_buf(),
            w,
            sample_schema,
            gap_schema,
            seq: 0,
            last_flush: Instant::now(),
        })
    }

    fn err(&self, e: mcap::McapError) -> FileError {
        FileError::Write {
            path: self.path.clone(),
            source: std::io::Error::other(e),
        }
    }

    /// Register a sensor's topics under `/tactile/<label>/`.
    pub fn add_sensor(
        &mut self,
        label: &str,
        meta: &[(String, String)],
    ) -> Result<SensorChannels, FileError> {
        let md: BTreeMap<String, String> = meta.iter().cloned().collect();
        let base = format!("/tactile/{}", label.trim_start_matches('/'));
        let raw = self
            .w
            .add_channel(0, &format!("{base}/raw"), RAW_ENCODING, &md)
            .map_err(|e| self.err(e))?;
        let sample = self
            .w
            .add_channel(
                self.sample_schema,
                &format!("{base}/sample"),
                cdr::MESSAGE_ENCODING,
                &md,
            )
            .map_err(|e| self.err(e))?;
        let gap = self
            .w
            .add_channel(
                self.gap_schema,
                &format!("{base}/gap"),
                cdr::MESSAGE_ENCODING,
                &md,
            )
            .map_err(|e| self.err(e))?;
        Ok(SensorChannels { raw, sample, gap })
    }

    /// One message; times in ns since the Unix epoch.
    pub fn write(
        &mut self,
        channel: u16,
        log_ns: u64,
        publish_ns: u64,
        data: &[u8],
    ) -> Result<(), FileError> {
        self.seq = self.seq.wrapping_add(1);
        let header = MessageHeader {
            channel_id: channel,
            sequence: self.seq,
            log_time: log_ns,
            publish_time: publish_ns,
        };
        self.w
            .write_to_known_channel(&header, data)
            .map_err(|e| self.err(e))
    }

    /// A metadata record `name` (e.g. one finger's clock estimate at the end of the run).
    pub fn metadata(&mut self, name: &str, pairs: &[(String, String)]) -> Result<(), FileError> {
        let metadata = pairs.iter().cloned().collect();
        let m = mcap::records::Metadata {
            name: name.to_string(),
            metadata,
        };
        self.w.write_metadata(&m).map_err(|e| self.err(e))
    }

    /// Close the current chunk and push it to the file.
    pub fn flush(&mut self) -> Result<(), FileError> {
        self.last_flush = Instant::now();
        self.w.flush().map_err(|e| self.err(e))
    }

    /// [`Self::flush`] unless the last was less than [`FLUSH_EVERY`] ago. Every sensor's
    /// recorder asks on its own schedule: sixteen sensors closing a chunk each would write
    /// sixteen times the chunks, and the writer keeps an index entry per chunk until the end.
    pub fn flush_due(&mut self) -> Result<(), FileError> {
        if self.last_flush.elapsed() >= FLUSH_EVERY {
            self.flush()?;
        }
        Ok(())
    }

    /// Write the summary and footer.
    pub fn finish(mut self) -> Result<(), FileError> {
        self.w.finish().map_err(|e| self.err(e))?;
        Ok(())
    }
}

/// A message read back from an MCAP file.
#[derive(Debug, Clone)]
pub struct StoredMessage {
    pub topic: Arc<str>,
    pub encoding: Arc<str>,
    pub log_ns: u64,
    pub publish_ns: u64,
    pub data: Vec<u8>,
}

/// What [`recover`] found.
#[derive(Debug)]
pub struct Recovered {
    pub messages: Vec<StoredMessage>,
    /// `None` for a complete file; otherwise why reading stopped (a writer killed mid-file).
    pub truncated: Option<String>,
}

/// Read every message of `path` in file order. A file whose writer was killed (no summary,
/// no footer, maybe half a chunk at the end) gives every message of its complete records and
/// says where it stopped.
pub fn recover(path: &Path) -> Result<Recovered, FileError> {
    let buf = std::fs::read(path).map_err(|e| FileError::open(path, e))?;
    recover_bytes(path, &buf)
}

/// MCAP record opcodes this reader acts on (MCAP specification, "Records").
mod op {
    pub const FOOTER: u8 = 0x02;
    pub const CHANNEL: u8 = 0x04;
    pub const MESSAGE: u8 = 0x05;
    pub const CHUNK: u8 = 0x06;
    pub const DATA_END: u8 = 0x0F;
}

/// [`recover`] of a file already in memory; `path` names it in messages.
///
/// Its own reader of the few records replay needs (channels, messages, uncompressed chunks)
/// rather than the `mcap` crate's: every length in the file is checked against the bytes that
/// are really there before use, so a corrupt file can neither allocate what it declares
/// (mcap 0.26 reserves a string's declared length, up to 4 GiB) nor overflow an offset
/// (mcap 0.26 panics in `sans_io::linear_reader`); both were found by the `replay` fuzz target.
pub fn recover_bytes(path: &Path, buf: &[u8]) -> Result<Recovered, FileError> {
    let Some(records) = buf.strip_prefix(MCAP_MAGIC) else {
        return Err(FileError::Capture {
            path: path.to_path_buf(),
            why: "not an MCAP file (bad magic)".into(),
        });
    };
    let mut r = Recovery::default();
    let truncated = match r.records(records, false) {
        Ok(true) => None,
        Ok(false) => Some("no footer: the writer stopped before finishing the file".into()),
        Err(why) => Some(why),
    };
    Ok(Recovered {
        messages: r.messages,
        truncated,
    })
}

/// The MCAP magic at the start (and end) of every MCAP file.
pub const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// Channels seen so far and the messages read.
#[derive(Default)]
struct Recovery {
    channels: BTreeMap<u16, (Arc<str>, Arc<str>)>,
    messages: Vec<StoredMessage>,
}

/// A cursor over one record's body that refuses to read past it.
struct Body<'a>(&'a [u8]);

impl<'a> Body<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        if n > self.0.len() {
            return Err(format!("a field of {n} bytes overruns its record"));
        }
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        Ok(head)
    }

    fn u16(&mut self) -> Result<u16, String> {
        Ok(u16::from_le_bytes(
            self.take(2)?.try_into().expect("2 bytes"),
        ))
    }

    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().expect("4 bytes"),
        ))
    }

    fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(
            self.take(8)?.try_into().expect("8 bytes"),
        ))
    }

    /// A `u64`-sized length that must fit in what is left.
    fn len64(&mut self) -> Result<usize, String> {
        let n = self.u64()?;
        usize::try_from(n)
            .ok()
            .filter(|&n| n <= self.0.len())
            .ok_or_else(|| format!("a length of {n} bytes overruns its record"))
    }

    fn string(&mut self) -> Result<&'a str, String> {
        let n = self.u32()? as usize;
        std::str::from_utf8(self.take(n)?).map_err(|_| "a string is not UTF-8".to_string())
    }
}

impl Recovery {
    /// Read records until the end of `bytes`; `Ok(true)` once the footer or data end is
    /// reached, `Ok(false)` if the bytes end between records, `Err` where a record is broken.
    /// Chunks do not nest (`in_chunk`), which also bounds the recursion.
    fn records(&mut self, mut bytes: &[u8], in_chunk: bool) -> Result<bool, String> {
        while !bytes.is_empty() {
            let mut head = Body(bytes);
            let opcode = head.take(1)?[0];
            let cut = |_| "a record is cut short (writer killed mid-record?)".to_string();
            let len = head.len64().map_err(cut)?;
            let body = head.take(len)?;
            bytes = head.0;
            match opcode {
                op::FOOTER | op::DATA_END => return Ok(true),
                op::CHANNEL => self.channel(Body(body))?,
                op::MESSAGE => self.message(Body(body))?,
                op::CHUNK if in_chunk => return Err("a chunk inside a chunk".into()),
                op::CHUNK if self.chunk(Body(body))? => return Ok(true),
                _ => {}
            }
        }
        Ok(false)
    }

    fn channel(&mut self, mut b: Body<'_>) -> Result<(), String> {
        let id = b.u16()?;
        let _schema_id = b.u16()?;
        let topic = b.string()?;
        let encoding = b.string()?;
        self.channels
            .entry(id)
            .or_insert_with(|| (Arc::from(topic), Arc::from(encoding)));
        Ok(())
    }

    fn message(&mut self, mut b: Body<'_>) -> Result<(), String> {
        let channel = b.u16()?;
        let _sequence = b.u32()?;
        let log_ns = b.u64()?;
        let publish_ns = b.u64()?;
        let (topic, encoding) =
            self.channels.get(&channel).cloned().ok_or_else(|| {
                format!("a message on channel {channel}, which no record declared")
            })?;
        self.messages.push(StoredMessage {
            topic,
            encoding,
            log_ns,
            publish_ns,
            data: b.0.to_vec(),
        });
        Ok(())
    }

    /// An uncompressed chunk's records (this writer never compresses).
    fn chunk(&mut self, mut b: Body<'_>) -> Result<bool, String> {
        let _start_ns = b.u64()?;
        let _end_ns = b.u64()?;
        let _uncompressed_size = b.u64()?;
        let _crc = b.u32()?;
        let compression = b.string()?;
        if !compression.is_empty() {
            return Err(format!(
                "a chunk compressed with {compression:?}, which this reader does not read"
            ));
        }
        let n = b.len64()?;
        self.records(b.take(n)?, true)
    }
}
