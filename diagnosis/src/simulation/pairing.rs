//! Which recording has which simulation (`tactile diagnose --simulation`, the Python package's
//! `simulation=` and `simulations=`): one simulation for every recording, one per recording in
//! the recordings' order, or a folder holding each recording's simulation under the
//! recording's own file name. A recording is found by the name its diagnosis is given: its path
//! as given, or its file name where that is unique (a session's rows name recordings so).

use std::path::{Path, PathBuf};

/// The simulations of a run, by recording.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Simulations {
    /// One simulation for every recording.
    all: Option<PathBuf>,
    /// Each recording's, under each name its diagnosis may be given.
    by_name: Vec<(String, PathBuf)>,
    /// A scale or travel beyond the plausible factor is taken on purpose
    /// (`super::plausible`).
    accept_scale: bool,
}

/// Simulations that cannot be paired with the recordings.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PairingError {
    /// Neither one for all, nor one per recording.
    #[error("{given} simulations for {recordings} recordings: give one per recording (in the recordings' order), one file for all of them, or one folder holding a simulation named as each recording")]
    Count { given: usize, recordings: usize },
    /// A simulation file that cannot be opened.
    #[error("simulation {}: {source}", .path.display())]
    Missing {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A folder of simulations without one for a recording.
    #[error("simulation folder {}: no file {name} for recording {}", .dir.display(), .recording.display())]
    NotInFolder {
        dir: PathBuf,
        name: String,
        recording: PathBuf,
    },
}

impl sysexit::ExitStatus for PairingError {
    fn exit_code(&self) -> u8 {
        match self {
            Self::Count { .. } => sysexit::USAGE,
            Self::Missing { source, .. } => sysexit::of_input(source.kind()),
            Self::NotInFolder { .. } => sysexit::NO_INPUT,
        }
    }
}

impl Simulations {
    /// `path` for every recording.
    pub fn one(path: impl Into<PathBuf>) -> Self {
        Self {
            all: Some(path.into()),
            by_name: Vec::new(),
            accept_scale: false,
        }
    }

    /// The same simulations, with a fitted scale or travel beyond the plausible factor taken
    /// on purpose (`--accept-scale`): the user says the simulation is in another unit, or of
    /// another gel, knowingly.
    pub fn accepting_scale(mut self, accept: bool) -> Self {
        self.accept_scale = accept;
        self
    }

    /// Whether a scale beyond the plausible factor is taken on purpose.
    pub fn accepts_scale(&self) -> bool {
        self.accept_scale
    }

    /// Pair `recordings` (files, as the run will name them) with `simulations`: one file for
    /// all, one folder holding `<recording's file name>` for each, or one file per recording in
    /// order. Every file is checked to be there.
    pub fn pair(recordings: &[PathBuf], simulations: &[PathBuf]) -> Result<Self, PairingError> {
        let files: Vec<PathBuf> = match simulations {
            [dir] if dir.is_dir() => recordings
                .iter()
                .map(|r| {
                    let name = file_name(r);
                    let path = dir.join(&name);
                    if path.is_file() {
                        Ok(path)
                    } else {
                        Err(PairingError::NotInFolder {
                            dir: dir.clone(),
                            name,
                            recording: r.clone(),
                        })
                    }
                })
                .collect::<Result<_, _>>()?,
            [one] => {
                exists(one)?;
                return Ok(Self::one(one.clone()));
            }
            _ if simulations.len() == recordings.len() => {
                simulations.iter().try_for_each(|s| exists(s))?;
                simulations.to_vec()
            }
            _ => {
                return Err(PairingError::Count {
                    given: simulations.len(),
                    recordings: recordings.len(),
                })
            }
        };
        let mut by_name = Vec::new();
        for (r, s) in recordings.iter().zip(files) {
            by_name.push((r.display().to_string(), s.clone()));
            let name = file_name(r);
            let unique = recordings.iter().filter(|o| file_name(o) == name).count() == 1;
            if unique && name != r.display().to_string() {
                by_name.push((name, s));
            }
        }
        Ok(Self {
            all: None,
            by_name,
            accept_scale: false,
        })
    }

    /// The simulation of the recording named `name` (its path as given, or its file name).
    pub fn for_recording(&self, name: &str) -> Option<&Path> {
        self.all.as_deref().or_else(|| {
            self.by_name
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, p)| p.as_path())
        })
    }
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}

/// Whether `path` can be opened as a file, as the error to give if not.
fn exists(path: &Path) -> Result<(), PairingError> {
    std::fs::File::open(path)
        .map(drop)
        .map_err(|source| PairingError::Missing {
            path: path.to_path_buf(),
            source,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(dir: &Path, name: &str) -> PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, "x").unwrap();
        p
    }

    #[test]
    fn pairs_in_order_by_folder_or_one_for_all() {
        let tmp = std::env::temp_dir().join(format!("tactile-pairing-{}", std::process::id()));
        let sims = tmp.join("sims");
        std::fs::create_dir_all(&sims).unwrap();
        let recs = vec![touch(&tmp, "a.csv"), touch(&tmp, "b.csv")];
        let (sa, sb) = (touch(&sims, "a.csv"), touch(&sims, "b.csv"));
        let ordered = Simulations::pair(&recs, &[sb.clone(), sa.clone()]).unwrap();
        assert_eq!(ordered.for_recording("a.csv"), Some(sb.as_path()));
        assert_eq!(
            ordered.for_recording(&recs[1].display().to_string()),
            Some(sa.as_path())
        );
        let folder = Simulations::pair(&recs, std::slice::from_ref(&sims)).unwrap();
        assert_eq!(folder.for_recording("b.csv"), Some(sb.as_path()));
        let all = Simulations::pair(&recs, std::slice::from_ref(&sa)).unwrap();
        assert_eq!(all.for_recording("anything"), Some(sa.as_path()));
        let three = Simulations::pair(&recs, &[sa.clone(), sb.clone(), sa]);
        assert!(matches!(three, Err(PairingError::Count { given: 3, .. })));
        std::fs::remove_file(&sb).unwrap();
        let gone = Simulations::pair(&recs, std::slice::from_ref(&sims));
        assert!(matches!(gone, Err(PairingError::NotInFolder { .. })));
        std::fs::remove_dir_all(&tmp).unwrap();
    }
}
