//! A TrueType font for plotters' text measurement (`ab_glyph`): labels are laid out from real
//! glyph widths, in SVG as in PNG, so tick labels and legends neither overlap nor get cut off.

use std::path::PathBuf;

use plotters::style::FontStyle;

use crate::Error;

/// Usual places of a sans-serif TrueType font, after `$TACTILE_FONT`.
const CANDIDATES: [&str; 4] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
];

/// Make plotters' `sans-serif` resolve to a system TrueType font; once per process.
pub fn register_font() -> Result<(), Error> {
    static DONE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        let mut candidates: Vec<PathBuf> = std::env::var_os("TACTILE_FONT")
            .map(PathBuf::from)
            .into_iter()
            .collect();
        candidates.extend(CANDIDATES.map(PathBuf::from));
        candidates
            .iter()
            .find_map(|p| std::fs::read(p).ok())
            .is_some_and(|bytes| {
                // plotters keeps the font for the process's lifetime.
                let leaked: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                plotters::style::register_font("sans-serif", FontStyle::Normal, leaked).is_ok()
            })
    });
    if ok {
        Ok(())
    } else {
        Err(Error::NoFont)
    }
}
