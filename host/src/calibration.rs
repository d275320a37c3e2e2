//! Storing a calibration on the device: the protocol's `SetCalibration` command from a fitted
//! (or modelled) calibration matrix.
//!
//! The device computes loads = C v with v the channel volts at the ADC input, i.e. after the
//! amplifiers (protocol SPEC, info field `calibration`), as f32. The least-squares fit itself
//! lives in `chip::calibration` (shared with the sim and the diagnosis); its offsets are not
//! sent (the device's tare and auto-null own the zero), nor a temperature column.

use std::fmt;

use chip::calibration::Fit;
use chip::sensitivity::{calibration_matrix_after_gains, Matrix3};
use chip::ChipParams;
use protocol::{Calibration, Command};

/// Why a matrix cannot be sent to the device.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum CalibrationError {
    /// An element is NaN or infinite.
    NonFinite {
        /// Row (load component) of the element.
        row: usize,
        /// Column (channel) of the element.
        col: usize,
    },
    /// A non-zero element is too large or too small to survive the conversion to f32.
    NotRepresentable {
        /// Row of the element.
        row: usize,
        /// Column of the element.
        col: usize,
        /// The value.
        value: f64,
    },
    /// The chip model's sensitivity matrix is singular or a gain is zero.
    NoModelMatrix,
}

impl fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite { row, col } => {
                write!(f, "calibration element [{row}][{col}] is not finite")
            }
            Self::NotRepresentable { row, col, value } => {
                write!(
                    f,
                    "calibration element [{row}][{col}] = {value:e} does not fit an f32"
                )
            }
            Self::NoModelMatrix => {
                write!(
                    f,
                    "the chip model gives no calibration matrix for these gains"
                )
            }
        }
    }
}

impl std::error::Error for CalibrationError {}

/// A matrix the device cannot hold is bad input data.
impl sysexit::ExitStatus for CalibrationError {
    fn exit_code(&self) -> u8 {
        sysexit::DATA
    }
}

/// The f32 matrix the device stores, checked element by element.
pub fn to_device_matrix(c: &Matrix3) -> Result<Calibration, CalibrationError> {
    let mut out = [[0.0_f32; 3]; 3];
    for (row, line) in c.iter().enumerate() {
        for (col, &value) in line.iter().enumerate() {
            if !value.is_finite() {
                return Err(CalibrationError::NonFinite { row, col });
            }
            let single = value as f32;
            let lost =
                !single.is_finite() || (value != 0.0 && (single == 0.0 || !single.is_normal()));
            if lost {
                return Err(CalibrationError::NotRepresentable { row, col, value });
            }
            out[row][col] = single;
        }
    }
    Ok(out)
}

/// `SetCalibration` for a matrix mapping ADC-input volts (Fz, Mx, My channels) to
/// (N, N·m, N·m).
pub fn set_calibration_command(c: &Matrix3) -> Result<Command, CalibrationError> {
    Ok(Command::SetCalibration(to_device_matrix(c)?))
}

/// `SetCalibration` for a least-squares fit made from ADC-input volts.
pub fn set_calibration_from_fit(fit: &Fit) -> Result<Command, CalibrationError> {
    set_calibration_command(&fit.matrix)
}

/// `SetCalibration` from the chip model, S^-1 diag(1/G), for amplifier gains `gains`: the
/// starting calibration before a fit.
pub fn model_set_calibration(p: &ChipParams, gains: [f64; 3]) -> Result<Command, CalibrationError> {
    let c = calibration_matrix_after_gains(p, gains).ok_or(CalibrationError::NoModelMatrix)?;
    set_calibration_command(&c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::{Accumulator, Message, Outcome, Request};

    #[test]
    fn model_calibration_reaches_the_wire_and_back() {
        let p = ChipParams::load_default().unwrap();
        let gains = [3000.0, 1000.0, 1000.0];
        let cmd = model_set_calibration(&p, gains).unwrap();
        let Command::SetCalibration(m) = cmd else {
            panic!("wrong command {cmd:?}")
        };
        let c = calibration_matrix_after_gains(&p, gains).unwrap();
        for i in 0..3 {
            for j in 0..3 {
                assert!(
                    (f64::from(m[i][j]) - c[i][j]).abs() <= 1e-7 * c[i][j].abs(),
                    "{m:?} vs {c:?}"
                );
            }
        }
        let msg = Message::Request(Request {
            tag: 7,
            command: cmd,
        });
        let bytes = protocol::encode_vec(&msg).unwrap();
        let mut acc = Accumulator::new();
        let got: Vec<Outcome> = acc.feed(&bytes).collect();
        assert_eq!(
            got,
            vec![Outcome::Message(msg)],
            "the device decodes the same matrix"
        );
    }

    #[test]
    fn bad_matrices_are_refused_with_the_element() {
        let mut c = [[1.0; 3]; 3];
        c[1][2] = f64::NAN;
        assert_eq!(
            set_calibration_command(&c),
            Err(CalibrationError::NonFinite { row: 1, col: 2 })
        );
        c[1][2] = 1e60;
        assert!(matches!(
            set_calibration_command(&c),
            Err(CalibrationError::NotRepresentable { row: 1, col: 2, .. })
        ));
        c[1][2] = 1e-60;
        assert!(matches!(
            set_calibration_command(&c),
            Err(CalibrationError::NotRepresentable { row: 1, col: 2, .. })
        ));
    }
}
