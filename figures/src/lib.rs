//! Shared plotting for tactile's figures (`tactile plot`, the diagnosis report): one look and
//! one set of rules for every axis, so a reader learns them once.
//!
//! - [`Ticks`]: axis ranges with ticks at round numbers;
//! - [`number`]: tick labels with just the decimals they need, SI-prefixed units instead of
//!   exponent form (`mV`, `kPa`), measurements as `6.08 ± 0.31 s`;
//! - [`Panel`] and [`draw_panel`]: one line chart with titled axes (`Fz bridge [mV]`), shaded
//!   bands, and its legend in a strip above the data, never over it; generic over the plotters
//!   backend, so PNG and SVG share it;
//! - [`svg_string`]: a figure as an SVG string, ready to inline into HTML.
//!
//! ```
//! use figures::{draw_panel, svg_string, Line, Panel, Quantity, styles};
//! let svg = svg_string((640, 240), |area| {
//!     let mut p = Panel::new(Quantity::new("time", "s"), Quantity::new("Fz bridge", "V"));
//!     p.lines.push(Line::new("recording", styles::RECORDING, vec![(0.0, 0.001), (1.0, 0.004)]));
//!     draw_panel(area, &p)
//! })
//! .unwrap();
//! assert!(svg.contains("Fz bridge [mV]"));
//! ```
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

mod chart;
mod font;
pub mod number;
mod ticks;

pub use chart::{draw_panel, segments, styles, svg_string, Band, Line, Panel, Quantity, Style};
pub use font::register_font;
pub use ticks::Ticks;

/// Why a figure could not be drawn.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Labels are measured with a TrueType font and none was found.
    #[error("no TrueType font found to lay out labels (set TACTILE_FONT to a .ttf file)")]
    NoFont,
    /// The drawing backend failed.
    #[error("drawing failed: {0}")]
    Draw(String),
}
