//! The session page's tables: the recordings with their protocol, verdict, own effects and
//! held-out misfit (or their error), and the shared effects with their parameters.

use super::headline::{pct, plain};
use super::output::{RecordingRow, SessionReport, SharedEffect};
use crate::output::EffectReport;
use crate::report::page::{esc, verdict_label};
use crate::report::{capital, params, words};

/// An effect's parameters as `name = value ± stderr unit`, one per line.
fn param_lines(e: &EffectReport) -> String {
    let rows = params::rows(&e.parameters, &e.params, Some(&e.param_stderr));
    let lines: Vec<String> = rows
        .iter()
        .map(|p| format!("<code>{}</code> = {}", esc(&p.name), esc(&p.value)))
        .collect();
    lines.join("<br>")
}

/// The recordings: protocol, verdict, own effects and held-out misfit, or the error in red.
pub(super) fn recordings(r: &SessionReport) -> String {
    let mut h = String::from(
        "<h2 id=recordings>Recordings</h2><p>Each recording's protocol, its verdict and the \
         effects that act on it alone; the held-out misfit (RMS over each channel's range, mean \
         of the compared channels) of its own baseline before and of the session's model after.\
         </p><table class=recordings><tr><th>file</th><th>contact angle</th><th>azimuth</th>\
         <th>rod speed</th><th>verdict</th><th>its own effects</th>\
         <th>held-out RMSE before → after</th></tr>",
    );
    for row in &r.recordings {
        h.push_str(&recording_row(row));
    }
    h.push_str("</table>");
    h
}

fn recording_row(row: &RecordingRow) -> String {
    let file = format!("<td><code>{}</code></td>", esc(&row.file));
    if let Some(e) = &row.error {
        return format!("<tr>{file}<td colspan=6 class=error>{}</td></tr>", esc(e));
    }
    let (angle, azimuth, speed) = row.protocol.map_or_else(Default::default, |p| {
        (
            format!("{}°", plain(p.contact_angle_deg)),
            format!("{}°", plain(p.azimuth_deg)),
            format!("{} mm/min", plain(p.rod_speed_mm_per_min)),
        )
    });
    let mut verdict = esc(row.verdict.map_or("", |v| verdict_label(v).1));
    // A recording the session's model does not explain: where it still misses most (the
    // rest under "Each recording").
    if let Some(rem) = &row.remains {
        let at = match rem.windows.first() {
            Some(m) => format!(
                "still misses {} during the {} at {}–{} s",
                words::channel_name(m.channel),
                m.regime,
                plain(m.t_start_s),
                plain(m.t_end_s)
            ),
            None => rem.character.clone(),
        };
        verdict.push_str(&format!("<br><small class=remains>{}</small>", esc(&at)));
    }
    let effects = match row.effects.as_deref() {
        None | Some([]) => "none".to_string(),
        Some(list) => list
            .iter()
            .map(|e| {
                // Where in the chain it acts: a relaxation of the sensing element is not the
                // gel's.
                format!(
                    "{} <small>({}: {})</small><br>{}",
                    esc(&words::effect_name(&e.name)),
                    e.stage.name(),
                    esc(&e.channels.join(", ")),
                    param_lines(e)
                )
            })
            .collect::<Vec<_>>()
            .join("<br>"),
    };
    let heldout = row.fit.as_ref().map_or(String::new(), |f| {
        format!(
            "{} → {}",
            pct(f.heldout.rmse_before),
            pct(f.heldout.rmse_after)
        )
    });
    format!(
        "<tr>{file}<td class=num>{}</td><td class=num>{}</td><td class=num>{}</td><td>{verdict}</td>\
         <td>{effects}</td><td class=num>{heldout}</td></tr>",
        esc(&angle),
        esc(&azimuth),
        esc(&speed)
    )
}

/// The effects with one parameter set for several recordings, the angle laws among them (as
/// OUT.json's `shared` lists them).
pub(super) fn shared(r: &SessionReport) -> String {
    let mut h = String::from("<h2 id=shared>Shared effects</h2>");
    let n = r.recordings.iter().filter(|x| x.error.is_none()).count();
    let rows: Vec<String> = r
        .shared
        .iter()
        .map(|s| {
            let e = &s.effect;
            let on = s
                .recordings
                .as_ref()
                .map_or_else(|| format!("all {n}"), |f| esc(&f.join(", ")));
            format!(
                "<tr><td>{}</td><td>{}</td><td>{}</td><td class=num>{}</td><td>{on}</td>\
                 <td>{}</td></tr>",
                esc(&capital(&words::effect_name(&e.name))),
                e.stage.name(),
                esc(&e.channels.join(", ")),
                shared_params(s),
                esc(&e.evidence)
            )
        })
        .collect();
    if rows.is_empty() {
        h.push_str("<p>None: no catalogue effect with one parameter set improved the session's fit and its held-out misfit enough to be kept, and no output's sensitivity follows the contact angle otherwise than the model's.</p>");
        return h;
    }
    h.push_str(
        "<p>One parameter set for the recordings named, fitted to all of them at once.</p>\
         <table class=shared><tr><th>effect</th><th>stage</th><th>channels</th>\
         <th>parameters</th><th>recordings</th><th>evidence</th></tr>",
    );
    h.push_str(&rows.concat());
    h.push_str("</table>");
    h
}

/// A shared effect's parameters, an output it names (`angle_dependence`'s `channel`) first.
fn shared_params(s: &SharedEffect) -> String {
    let lines = param_lines(&s.effect);
    match &s.channel_param {
        Some(ch) => format!("<code>channel</code> = {}<br>{lines}", esc(ch)),
        None => lines,
    }
}

#[cfg(test)]
mod tests {
    use super::super::headline::plain;

    #[test]
    fn protocol_values_read_as_written() {
        assert_eq!(plain(20.0), "20");
        assert_eq!(plain(0.0), "0");
        assert_eq!(plain(22.5), "22.5");
        assert_eq!(plain(0.25), "0.25");
        assert_eq!(plain(600.0), "600");
    }
}
