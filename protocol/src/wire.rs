//! Little-endian cursor over a message body. Reading past the end is an error, never a panic.

/// Writes fields into a fixed buffer. The caller sizes the buffer from the message's known
/// length, so running out of room is a programmer error caught by the encoder's length check.
pub(crate) struct Writer<'a> {
    buf: &'a mut [u8],
    pos: usize,
}

impl<'a> Writer<'a> {
    pub(crate) fn new(buf: &'a mut [u8]) -> Self {
        Self { buf, pos: 0 }
    }

    pub(crate) fn len(&self) -> usize {
        self.pos
    }

    /// Append `bytes`; returns `false` (and writes nothing) if they do not fit.
    pub(crate) fn bytes(&mut self, bytes: &[u8]) -> bool {
        let end = self.pos + bytes.len();
        match self.buf.get_mut(self.pos..end) {
            Some(dst) => {
                dst.copy_from_slice(bytes);
                self.pos = end;
                true
            }
            None => false,
        }
    }

    pub(crate) fn u8(&mut self, v: u8) -> bool {
        self.bytes(&[v])
    }
    pub(crate) fn u16(&mut self, v: u16) -> bool {
        self.bytes(&v.to_le_bytes())
    }
    pub(crate) fn u32(&mut self, v: u32) -> bool {
        self.bytes(&v.to_le_bytes())
    }
    pub(crate) fn i32(&mut self, v: i32) -> bool {
        self.bytes(&v.to_le_bytes())
    }
    pub(crate) fn f32(&mut self, v: f32) -> bool {
        self.bytes(&v.to_le_bytes())
    }
    /// A 24-bit two's-complement ADC code; the top byte of `v` is dropped.
    pub(crate) fn i24(&mut self, v: i32) -> bool {
        let b = v.to_le_bytes();
        self.bytes(&b[..3])
    }
}

/// Reads fields from a received body.
pub(crate) struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

/// The body ended before a field did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Short;

impl<'a> Reader<'a> {
    pub(crate) fn new(buf: &'a [u8]) -> Self {
        Self { buf, pos: 0 }
    }

    pub(crate) fn remaining(&self) -> usize {
        self.buf.len() - self.pos
    }

    fn take<const K: usize>(&mut self) -> Result<[u8; K], Short> {
        let bytes = self.buf.get(self.pos..self.pos + K).ok_or(Short)?;
        self.pos += K;
        let mut out = [0; K];
        out.copy_from_slice(bytes);
        Ok(out)
    }

    pub(crate) fn u8(&mut self) -> Result<u8, Short> {
        Ok(self.take::<1>()?[0])
    }
    pub(crate) fn u16(&mut self) -> Result<u16, Short> {
        Ok(u16::from_le_bytes(self.take()?))
    }
    pub(crate) fn u32(&mut self) -> Result<u32, Short> {
        Ok(u32::from_le_bytes(self.take()?))
    }
    pub(crate) fn i32(&mut self) -> Result<i32, Short> {
        Ok(i32::from_le_bytes(self.take()?))
    }
    pub(crate) fn f32(&mut self) -> Result<f32, Short> {
        Ok(f32::from_le_bytes(self.take()?))
    }
    /// A 24-bit two's-complement code, sign-extended to 32 bits.
    pub(crate) fn i24(&mut self) -> Result<i32, Short> {
        let [a, b, c] = self.take::<3>()?;
        Ok(i32::from_le_bytes([a, b, c, 0]) << 8 >> 8)
    }
}
