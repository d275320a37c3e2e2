//! The one loader for every parameter in `hardware/*.toml` (chip, material, front end, ADC, board).
