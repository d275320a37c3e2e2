use super::*;

fn row(file: &str, outcome: Result<Outcome, String>) -> Row {
    Row {
        file: file.to_string(),
        stem: stem_of(Path::new(file)),
        seconds: 1.5,
        outcome,
    }
}

fn ok(effects: &[(&str, &str, f64, Option<f64>)]) -> Result<Outcome, String> {
    Ok(Outcome {
        verdict: "explained".to_string(),
        effects: effects
            .iter()
            .map(|&(effect, name, value, stderr)| Param {
                effect: effect.to_string(),
                name: name.to_string(),
                value,
                stderr,
            })
            .collect(),
        modulus_pa: 25e3,
        load_scale: None,
        heldout_rmse: (0.02, 0.004),
    })
}

fn session() -> Vec<Row> {
    vec![
        row(
            "a.csv",
            ok(&[("highpass_coupling", "tau_s", 40.0, Some(1.0))]),
        ),
        row(
            "b,1.csv",
            Err("b,1.csv: line 3: \"x\" is not a number".to_string()),
        ),
        row(
            "c.csv",
            ok(&[
                ("viscoelastic_relaxation", "tau_s", 4.0, Some(0.1)),
                ("highpass_coupling", "tau_s", 41.0, None),
            ]),
        ),
    ]
}

#[test]
fn the_table_has_a_column_pair_per_parameter_in_catalogue_order() {
    let t = table::table(&session());
    let params: Vec<&str> = t.header[5..9].iter().map(String::as_str).collect();
    assert_eq!(
        params,
        [
            "viscoelastic_relaxation.tau_s",
            "viscoelastic_relaxation.tau_s_stderr",
            "highpass_coupling.tau_s",
            "highpass_coupling.tau_s_stderr"
        ]
    );
    assert!(t.rows.iter().all(|r| r.len() == t.header.len()));
}

#[test]
fn summary_csv_quotes_per_rfc_4180_and_keeps_input_order() {
    let text = csv::summary(&session());
    let lines: Vec<&str> = text.split_terminator("\r\n").collect();
    assert_eq!(lines.len(), 4, "{text}");
    assert!(lines[1].starts_with("a.csv,ok,explained,highpass_coupling,25000,,,40,1,"));
    assert!(
        lines[2].starts_with("\"b,1.csv\",error,")
            && lines[2].ends_with(",1.5,\"b,1.csv: line 3: \"\"x\"\" is not a number\""),
        "{}",
        lines[2]
    );
    assert!(lines[3].contains("viscoelastic_relaxation+highpass_coupling"));
}

#[test]
fn summary_html_has_a_plot_per_parameter_and_no_external_reference() {
    let html = html::summary(&session());
    // The modulus and the two effect parameters.
    assert_eq!(html.matches("<svg").count(), 3, "{html}");
    assert!(html.contains("tau_s [s]") && html.contains("youngs_modulus_Pa [Pa]"));
    // The only address is the SVG namespace, which is a name, not a fetch.
    let svg_ns = "http://www.w3.org/2000/svg";
    assert_eq!(html.matches("http").count(), html.matches(svg_ns).count());
    assert!(!html.contains("src=") && !html.contains("<link") && !html.contains("<script"));
}

#[test]
fn folders_expand_to_their_csv_files_sorted_and_stems_must_differ() {
    let dir = std::env::temp_dir().join(format!("tactile-session-{}", std::process::id()));
    let sub = dir.join("sub");
    std::fs::create_dir_all(&sub).unwrap();
    for name in ["b.csv", "a.csv", "notes.txt"] {
        std::fs::write(dir.join(name), name).unwrap();
    }
    let got = expand_inputs(std::slice::from_ref(&dir)).unwrap();
    assert_eq!(got, [dir.join("a.csv"), dir.join("b.csv")]);
    std::fs::write(sub.join("a.csv"), "another a").unwrap();
    let err = expand_inputs(&[dir.clone(), sub.join("a.csv")]).unwrap_err();
    assert!(
        matches!(err, SessionError::SameStem { ref stem, .. } if stem == "a"),
        "{err}"
    );
    // The message says what would happen: both outputs in one place, not two inputs clashing.
    assert!(
        err.to_string()
            .contains("would both be written to a.json and a.html in the output folder"),
        "{err}"
    );
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    assert!(matches!(
        expand_inputs(&[empty]),
        Err(SessionError::Input(
            crate::inputs::InputError::NoRecordings(_)
        ))
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}
