//! The MCAP side of a recording: every received frame as raw wire bytes (re-decodable by
//! `tactile replay`), every sample decoded to JSON with both timestamps (plots directly in
//! Foxglove), gaps and info frames. Chunks are uncompressed and closed at every flush, so a
//! killed logger leaves complete chunks that [`recover`] reads back.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use mcap::records::MessageHeader;

use super::FileError;

/// Encoding label of the raw topic: COBS frames of protocol/SPEC.md without delimiter.
pub const RAW_ENCODING: &str = "tactile-cobs-v1";

const SAMPLE_SCHEMA: &str = r#"{"type":"object","title":"tactile.Sample","properties":{
"t_s":{"type":"number","description":"s since the start of the recording"},
"t_device_s":{"type":"number","description":"device clock, s, unwrapped"},
"t_host_s":{"type":"number","description":"host receive time of the frame, Unix s"},
"seq":{"type":"integer"},"session":{"type":"integer"},
"fz_V":{"type":"number"},"mx_V":{"type":"number"},"my_V":{"type":"number"},
"fz_N":{"type":"number"},"mx_Nm":{"type":"number"},"my_Nm":{"type":"number"},
"temp_code":{"type":"integer"},"saturated":{"type":"integer"}}}"#;

const GAP_SCHEMA: &str = r#"{"type":"object","title":"tactile.Gap","properties":{
"t_s":{"type":"number"},"kind":{"type":"string"},"missing":{"type":"integer"},"session":{"type":"integer"}}}"#;

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
            .add_schema("tactile.Sample", "jsonschema", SAMPLE_SCHEMA.as_bytes())
            .map_err(err)?;
        let gap_schema = w
            .add_schema("tactile.Gap", "jsonschema", GAP_SCHEMA.as_bytes())
            .map_err(err)?;
        Ok(Self {
            path: path.to_path_buf(),
            w,
            sample_schema,
            gap_schema,
            seq: 0,
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
            .add_channel(self.sample_schema, &format!("{base}/sample"), "json", &md)
            .map_err(|e| self.err(e))?;
        let gap = self
            .w
            .add_channel(self.gap_schema, &format!("{base}/gap"), "json", &md)
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

    /// Close the current chunk and push it to the file.
    pub fn flush(&mut self) -> Result<(), FileError> {
        self.w.flush().map_err(|e| self.err(e))
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
/// no footer, maybe half a chunk at the end) gives every message of its complete chunks and
/// says where it stopped.
pub fn recover(path: &Path) -> Result<Recovered, FileError> {
    let buf = std::fs::read(path).map_err(|e| FileError::open(path, e))?;
    recover_bytes(path, &buf)
}

/// [`recover`] of a file already in memory; `path` names it in messages.
pub fn recover_bytes(path: &Path, buf: &[u8]) -> Result<Recovered, FileError> {
    let stream =
        mcap::MessageStream::new_with_options(buf, mcap::read::Options::IgnoreEndMagic.into())
            .map_err(|e| FileError::Capture {
                path: path.to_path_buf(),
                why: format!("not an MCAP file ({e})"),
            })?;
    let mut messages = Vec::new();
    let mut truncated = None;
    let mut topics: BTreeMap<u16, (Arc<str>, Arc<str>)> = BTreeMap::new();
    for m in stream {
        match m {
            Ok(m) => {
                let (topic, encoding) = topics
                    .entry(m.channel.id)
                    .or_insert_with(|| {
                        (
                            Arc::from(m.channel.topic.as_str()),
                            Arc::from(m.channel.message_encoding.as_str()),
                        )
                    })
                    .clone();
                let data = match m.data {
                    Cow::Borrowed(b) => b.to_vec(),
                    Cow::Owned(v) => v,
                };
                messages.push(StoredMessage {
                    topic,
                    encoding,
                    log_ns: m.log_time,
                    publish_ns: m.publish_time,
                    data,
                });
            }
            Err(e) => {
                truncated = Some(e.to_string());
                break;
            }
        }
    }
    Ok(Recovered {
        messages,
        truncated,
    })
}
