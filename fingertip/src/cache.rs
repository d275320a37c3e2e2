//! Disk and in-process cache of FE compression curves: a curve is the FE run's output for a
//! [`Config`], so it is stored beside the model that computes it.
//!
//! A curve costs seconds of FE; a diagnosis needs one or two, the proof a dozen, each many
//! times. Curves live in `$TACTILE_CACHE_DIR`, else `$XDG_CACHE_HOME/tactile`, else
//! `~/.cache/tactile`, under `fe-curves/`, one JSON file per key. The key is every input of the
//! FE run (the whole `fingertip::Config`, the load reached, the step) plus this crate's version
//! and [`CURVE_REVISION`]; the file repeats the key, so a hash collision or a stale file is
//! recomputed, not used. Writers write a private temporary file and rename it into place
//! (atomic on one file system), so concurrent writers race harmlessly and a reader never sees
//! half a file; a corrupt or unreadable file is recomputed and replaced. Without a cache
//! directory the curve is computed in memory. Within a process each key is computed once
//! (other threads asking for it wait).

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, OnceLock};

use crate::Config;

/// Bump when the meaning of a stored curve changes without a change of its inputs (the FE's
/// chip-load extraction, the stepping). 3: the FE's chip loads count the package top only, and
/// its contact onset is sharper.
pub const CURVE_REVISION: u32 = 3;
/// Environment variable that overrides the cache directory.
pub const CACHE_DIR_ENV: &str = "TACTILE_CACHE_DIR";

/// FE samples at the configured modulus: rod travel (mm), rod force (N) and the FE's resultant
/// on the package [fx, fy, fz (N), mx, my (N·m)].
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RawCurve {
    pub rod_mm: Vec<f64>,
    pub force_n: Vec<f64>,
    pub package: Vec<[f64; 5]>,
}

impl RawCurve {
    pub fn push(&mut self, rod_mm: f64, force_n: f64, package: [f64; 5]) {
        self.rod_mm.push(rod_mm);
        self.force_n.push(force_n);
        self.package.push(package);
    }

    pub fn points(&self) -> impl Iterator<Item = (f64, f64, [f64; 5])> + '_ {
        self.rod_mm
            .iter()
            .zip(&self.force_n)
            .zip(&self.package)
            .map(|((&r, &f), &p)| (r, f, p))
    }

    /// Same lengths, at least two points, finite, travel increasing.
    fn is_valid(&self) -> bool {
        let n = self.rod_mm.len();
        n >= 2
            && self.force_n.len() == n
            && self.package.len() == n
            && self.rod_mm.windows(2).all(|w| w[1] > w[0])
            && self
                .points()
                .all(|(r, f, p)| r.is_finite() && f.is_finite() && p.iter().all(|v| v.is_finite()))
    }
}

#[derive(serde::Serialize, serde::Deserialize)]
struct File {
    key: String,
    curve: RawCurve,
}

type Slot = Arc<OnceLock<Result<Arc<RawCurve>, String>>>;

fn memo() -> &'static Mutex<HashMap<String, Slot>> {
    static MEMO: OnceLock<Mutex<HashMap<String, Slot>>> = OnceLock::new();
    MEMO.get_or_init(Default::default)
}

/// Drop this process's in-memory curves (the disk cache stays): for timing studies.
pub fn forget_in_memory() {
    memo().lock().unwrap_or_else(|e| e.into_inner()).clear();
}

/// The cache directory, if there is one.
pub fn cache_dir() -> Option<PathBuf> {
    let env = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    let base = env(CACHE_DIR_ENV)
        .or_else(|| env("XDG_CACHE_HOME").map(|d| d.join("tactile")))
        .or_else(|| env("HOME").map(|d| d.join(".cache").join("tactile")))?;
    Some(base.join("fe-curves"))
}

/// The key of one FE run: every input, the crate version and the revision.
pub fn key(config: &Config, reach_n: f64, step_fraction: f64) -> String {
    format!(
        "rev {CURVE_REVISION}; host {}; reach_n {reach_n:e}; step {step_fraction:e}; {}",
        env!("CARGO_PKG_VERSION"),
        serde_json::to_string(config).unwrap_or_default()
    )
}

/// FNV-1a, 64 bit: a stable file name for a key (std's hasher may change between releases).
fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

fn path_of(dir: &std::path::Path, key: &str) -> PathBuf {
    dir.join(format!("fe-{:016x}.json", fnv1a(key)))
}

/// The stored curve for `key`, if a valid one is there.
fn load(dir: &std::path::Path, key: &str) -> Option<RawCurve> {
    let text = std::fs::read_to_string(path_of(dir, key)).ok()?;
    let file: File = serde_json::from_str(&text).ok()?;
    (file.key == key && file.curve.is_valid()).then_some(file.curve)
}

/// Store atomically; a failure only costs a recomputation next time.
fn store(dir: &std::path::Path, key: &str, curve: &RawCurve) {
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let Ok(text) = serde_json::to_string(&File {
        key: key.to_string(),
        curve: curve.clone(),
    }) else {
        return;
    };
    let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let tmp = dir.join(format!(
        ".tmp-{}-{n}-{:016x}",
        std::process::id(),
        fnv1a(key)
    ));
    let ok = std::fs::create_dir_all(dir).is_ok() && std::fs::write(&tmp, text).is_ok();
    if !ok || std::fs::rename(&tmp, path_of(dir, key)).is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
}

/// Why a curve is not there: `compute` failed now, or an earlier attempt at the same key in
/// this process failed (its message: the error itself went to that caller).
#[derive(Debug)]
pub enum Failed<E> {
    /// This call's computation failed.
    Now(E),
    /// An earlier call's computation of the same key failed.
    Earlier(String),
}

/// The curve for these inputs: from this process's memory, the disk cache, or `compute`.
pub fn get_or_compute<E: std::fmt::Display>(
    config: &Config,
    reach_n: f64,
    step_fraction: f64,
    compute: impl FnOnce() -> Result<RawCurve, E>,
) -> Result<Arc<RawCurve>, Failed<E>> {
    let key = key(config, reach_n, step_fraction);
    let slot = memo()
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .entry(key.clone())
        .or_default()
        .clone();
    let mut error = None;
    let result = slot.get_or_init(|| {
        let dir = cache_dir();
        if let Some(curve) = dir.as_deref().and_then(|d| load(d, &key)) {
            return Ok(Arc::new(curve));
        }
        match compute() {
            Ok(curve) => {
                if let Some(d) = dir.as_deref() {
                    store(d, &key, &curve);
                }
                Ok(Arc::new(curve))
            }
            Err(e) => {
                let text = e.to_string();
                error = Some(e);
                Err(text)
            }
        }
    });
    match (result, error) {
        (Ok(c), _) => Ok(c.clone()),
        (Err(_), Some(e)) => Err(Failed::Now(e)),
        (Err(text), None) => Err(Failed::Earlier(text.clone())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve() -> RawCurve {
        let mut c = RawCurve::default();
        c.push(0.0, 0.0, [0.0; 5]);
        c.push(1.0, 2.0, [0.1, 0.2, -0.3, 0.4, 0.5]);
        c
    }

    fn scratch(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("tactile-fe-cache-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    /// Stored curves come back; a corrupt file, another key's file or an invalid curve do not.
    #[test]
    fn round_trip_and_corrupt_files() {
        let dir = scratch("roundtrip");
        store(&dir, "k1", &curve());
        assert_eq!(load(&dir, "k1"), Some(curve()));
        assert_eq!(load(&dir, "k2"), None);
        std::fs::write(
            path_of(&dir, "k1"),
            "{\"key\": \"k1\", \"curve\": {\"rod_mm\": [0",
        )
        .unwrap();
        assert_eq!(load(&dir, "k1"), None);
        let mut bad = curve();
        bad.rod_mm[1] = 0.0;
        store(&dir, "k3", &bad);
        assert_eq!(load(&dir, "k3"), None);
        let leftovers = std::fs::read_dir(&dir).unwrap().filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .starts_with(".tmp")
        });
        assert_eq!(leftovers.count(), 0);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Many writers of one key at once leave one valid file.
    #[test]
    fn concurrent_writers() {
        let dir = scratch("concurrent");
        std::thread::scope(|s| {
            for _ in 0..8 {
                s.spawn(|| store(&dir, "k", &curve()));
            }
        });
        assert_eq!(load(&dir, "k"), Some(curve()));
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The key changes with every input.
    #[test]
    fn key_covers_the_inputs() {
        let a = Config::from_hardware(&hardware::Params::load_default().unwrap().fingertip, 2.0);
        let mut b = a.clone();
        b.poisson = 0.48;
        assert_ne!(key(&a, 75.0, 0.04), key(&b, 75.0, 0.04));
        assert_ne!(key(&a, 75.0, 0.04), key(&a, 70.0, 0.04));
        assert_ne!(key(&a, 75.0, 0.04), key(&a, 75.0, 0.05));
        assert_eq!(key(&a, 75.0, 0.04), key(&a.clone(), 75.0, 0.04));
    }
}
