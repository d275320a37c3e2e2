//! The MCAP messages' binary form: ROS 2 message definitions (`ros2msg` schemas, written into
//! the file) with CDR-encoded messages, which Foxglove, the `mcap` tools and any ROS 2 reader
//! decode from the schema alone. Little-endian CDR: a 4-byte encapsulation header
//! (`00 01 00 00`), then each field in order, aligned to its own size counted from after the
//! header; a string is its length (with its NUL) as `uint32`, its bytes and a NUL; a sequence
//! (`float64[]`) its length as `uint32`, then its elements.
//!
//! A frame of ten samples is one message of 732 bytes, written with no formatting at all.

/// The samples of one frame: field order of [`SAMPLE_SCHEMA`]. One message per frame, not per
/// sample: the frame's own values once, each sample's in arrays (a tenth of the messages, and
/// of their headers and index entries, for the same numbers).
pub const SAMPLE_NAME: &str = "tactile/msg/Samples";
pub const SAMPLE_SCHEMA: &str = "\
# The samples of one frame of a fingertip, oldest first: one element per sample in every array
# (docs/recording-format.md and docs/hand.md have the columns of the same names).
float64 t_host_s      # when the host read the frame, Unix s
uint32 seq            # the frame's sequence number
uint32 session        # connection session
int32 temp_code       # raw code of ADC channel 3 (temperature sensor)
uint8 saturated       # a channel clipped
float64[] t_s         # s since the start of the recording, on the host time base of all fingers
float64[] t_device_s  # the device's clock, s, unwrapped within a session
float64[] fz_v        # bridge outputs at the ADC input, V
float64[] mx_v
float64[] my_v
float64[] fz_n        # loads through the calibration matrix, N and N m
float64[] mx_nm
float64[] my_nm
";

pub const GAP_NAME: &str = "tactile/msg/Gap";
pub const GAP_SCHEMA: &str = "\
# Why the stream is not continuous at this point.
float64 t_s         # s since the start of the recording
string kind         # sequence, disconnected, reconnected, device_restart, host_queue_full
int64 missing       # frames missing, -1 when unknown
uint32 session
";

/// The schema encoding and message encoding named in the MCAP file.
pub const SCHEMA_ENCODING: &str = "ros2msg";
pub const MESSAGE_ENCODING: &str = "cdr";

/// Little-endian CDR encapsulation header.
const HEADER: [u8; 4] = [0, 1, 0, 0];

/// A CDR message being built in a reused buffer.
#[derive(Debug, Default)]
pub struct CdrWriter {
    pub buf: Vec<u8>,
}

impl CdrWriter {
    /// Start a new message (the buffer keeps its capacity).
    pub fn begin(&mut self) -> &mut Self {
        self.buf.clear();
        self.buf.extend_from_slice(&HEADER);
        self
    }

    fn align(&mut self, n: usize) {
        while (self.buf.len() - HEADER.len()) % n != 0 {
            self.buf.push(0);
        }
    }

    pub fn f64(&mut self, v: f64) -> &mut Self {
        self.align(8);
        self.buf.extend_from_slice(&v.to_le_bytes());
        self
    }

    pub fn i64(&mut self, v: i64) -> &mut Self {
        self.align(8);
        self.buf.extend_from_slice(&v.to_le_bytes());
        self
    }

    pub fn u32(&mut self, v: u32) -> &mut Self {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
        self
    }

    pub fn i32(&mut self, v: i32) -> &mut Self {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
        self
    }

    pub fn u8(&mut self, v: u8) -> &mut Self {
        self.buf.push(v);
        self
    }

    /// An unbounded sequence (`float64[]`): its length as `uint32`, then its elements.
    pub fn f64s(&mut self, v: &[f64]) -> &mut Self {
        self.u32(v.len() as u32);
        self.align(8);
        for x in v {
            self.buf.extend_from_slice(&x.to_le_bytes());
        }
        self
    }

    pub fn string(&mut self, s: &str) -> &mut Self {
        self.u32(s.len() as u32 + 1);
        self.buf.extend_from_slice(s.as_bytes());
        self.buf.push(0);
        self
    }
}

/// A decoded field value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Float(f64),
    Int(i64),
    Text(String),
    /// A sequence (`type[]`) of numbers.
    List(Vec<Value>),
}

impl Value {
    /// The value as a number (text, a list: NaN).
    pub fn num(&self) -> f64 {
        match self {
            Self::Float(v) => *v,
            Self::Int(v) => *v as f64,
            Self::Text(_) | Self::List(_) => f64::NAN,
        }
    }

    /// A list's elements as numbers; a single value as a list of one.
    pub fn nums(&self) -> Vec<f64> {
        match self {
            Self::List(v) => v.iter().map(Self::num).collect(),
            v => vec![v.num()],
        }
    }
}

/// The fields of a `ros2msg` schema of primitive fields and unbounded sequences of primitive
/// numbers (`float64[]`): (type, name) in order. Comments, blank lines and constants
/// (`type NAME=value`) are skipped; anything else is refused.
pub fn parse_schema(text: &str) -> Result<Vec<(String, String)>, String> {
    let mut fields = Vec::new();
    for (no, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() || line.contains('=') {
            continue;
        }
        let mut it = line.split_whitespace();
        let (Some(ty), Some(name), None) = (it.next(), it.next(), it.next()) else {
            return Err(format!("schema line {}: not `type name`: {line:?}", no + 1));
        };
        let element = ty.strip_suffix("[]").unwrap_or(ty);
        if size_of_type(element).is_none() || (element != ty && element == "string") {
            return Err(format!("schema line {}: type {ty:?} not supported", no + 1));
        }
        fields.push((ty.to_string(), name.to_string()));
    }
    Ok(fields)
}

/// Alignment (= size) of a primitive type; 4 for a string (its length).
fn size_of_type(ty: &str) -> Option<usize> {
    Some(match ty {
        "bool" | "byte" | "char" | "int8" | "uint8" => 1,
        "int16" | "uint16" => 2,
        "int32" | "uint32" | "float32" | "string" => 4,
        "int64" | "uint64" | "float64" => 8,
        _ => return None,
    })
}

/// Decode one CDR message through the fields of [`parse_schema`].
pub fn decode(fields: &[(String, String)], msg: &[u8]) -> Result<Vec<(String, Value)>, String> {
    let body = msg
        .strip_prefix(&HEADER)
        .ok_or("not little-endian CDR (encapsulation header)")?;
    let mut r = Reader { body, at: 0 };
    let mut out = Vec::with_capacity(fields.len());
    for (ty, name) in fields {
        let short = |e: String| format!("field {name}: {e}");
        let v = match ty.strip_suffix("[]") {
            Some(element) => {
                let n = r.primitive("uint32").map_err(short)?.num() as usize;
                // A length is checked against the bytes there before anything is reserved.
                let size = size_of_type(element).ok_or("unsupported type")?;
                if n.saturating_mul(size) > body.len() {
                    return Err(short(format!("a sequence of {n} overruns the message")));
                }
                let items = (0..n).map(|_| r.primitive(element));
                Value::List(items.collect::<Result<_, _>>().map_err(short)?)
            }
            None => r.primitive(ty).map_err(short)?,
        };
        out.push((name.clone(), v));
    }
    Ok(out)
}

/// A cursor over a CDR body (offsets count from after the encapsulation header).
struct Reader<'a> {
    body: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let b = self
            .body
            .get(self.at..self.at + n)
            .ok_or("message too short")?;
        self.at += n;
        Ok(b)
    }

    /// One primitive field, aligned to its size.
    fn primitive(&mut self, ty: &str) -> Result<Value, String> {
        let n = size_of_type(ty).ok_or("unsupported type")?;
        self.at = self.at.next_multiple_of(n);
        let b = self.take(n)?;
        Ok(match ty {
            "float64" => Value::Float(f64::from_le_bytes(b.try_into().expect("8"))),
            "float32" => Value::Float(f64::from(f32::from_le_bytes(b.try_into().expect("4")))),
            "int64" => Value::Int(i64::from_le_bytes(b.try_into().expect("8"))),
            "uint64" => Value::Int(u64::from_le_bytes(b.try_into().expect("8")) as i64),
            "int32" => Value::Int(i64::from(i32::from_le_bytes(b.try_into().expect("4")))),
            "uint32" => Value::Int(i64::from(u32::from_le_bytes(b.try_into().expect("4")))),
            "int16" => Value::Int(i64::from(i16::from_le_bytes(b.try_into().expect("2")))),
            "uint16" => Value::Int(i64::from(u16::from_le_bytes(b.try_into().expect("2")))),
            "int8" => Value::Int(i64::from(b[0] as i8)),
            "string" => {
                let len = u32::from_le_bytes(b.try_into().expect("4")) as usize;
                let s = self.take(len)?;
                let s = s.strip_suffix(&[0]).unwrap_or(s);
                Value::Text(String::from_utf8_lossy(s).into_owned())
            }
            _ => Value::Int(i64::from(b[0])),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gap_round_trips_through_its_schema() {
        let mut w = CdrWriter::default();
        w.begin().f64(1.5).string("reconnected").i64(-1).u32(3);
        let fields = parse_schema(GAP_SCHEMA).expect("schema");
        let v = decode(&fields, &w.buf).expect("decodes");
        assert_eq!(v[0], ("t_s".into(), Value::Float(1.5)));
        assert_eq!(v[1], ("kind".into(), Value::Text("reconnected".into())));
        assert_eq!(v[2], ("missing".into(), Value::Int(-1)));
        assert_eq!(v[3], ("session".into(), Value::Int(3)));
    }

    /// A frame's message: its own fields once, then one array element per sample.
    #[test]
    fn a_frame_of_samples_round_trips_through_its_schema() {
        let f = parse_schema(SAMPLE_SCHEMA).expect("schema");
        assert_eq!(f.len(), 13);
        assert_eq!(f[4], ("uint8".into(), "saturated".into()));
        assert_eq!(f[12], ("float64[]".into(), "my_nm".into()));
        let mut w = CdrWriter::default();
        w.begin().f64(1.7e9).u32(7).u32(1).i32(-3).u8(1);
        let t: Vec<f64> = (0..10).map(|k| f64::from(k) * 1e-3).collect();
        for _ in 0..8 {
            w.f64s(&t);
        }
        let v = decode(&f, &w.buf).expect("decodes");
        assert_eq!(v[1], ("seq".into(), Value::Int(7)));
        assert_eq!(v[3], ("temp_code".into(), Value::Int(-3)));
        assert_eq!(v[5].0, "t_s");
        assert_eq!(v[12].1.nums(), t);
        assert_eq!(w.buf.len(), 732);
        assert!(decode(&f, &w.buf[..w.buf.len() - 8]).is_err());
    }
}
