//! What a command will do, checked before anything runs: the tasks, methods and seeds, the
//! config file and the output folder (resolved to an absolute path and refused inside
//! `fixtures/`, which only `regen-fixtures` writes).

use std::fmt::Write as _;
use std::io;
use std::path::{Component, Path, PathBuf};

use thiserror::Error;

use crate::cli::{Readings, ReproduceArgs};
use eamadm::paper::PaperTask;

/// Seeds per task and method of a `--quick` run: the facade's ([`eamadm::QUICK_SEEDS`]), which
/// Python's `eamadm.run(..., quick=True)` uses too.
pub(crate) const QUICK_SEEDS: u32 = eamadm::QUICK_SEEDS;

/// The method labels of the embedded default configs, in order of first appearance: the four
/// methods, the ablations (each EA-MADM with one switch flipped), then the maze tasks'
/// controls ([`eamadm::paper::controls`]).
pub(crate) fn default_methods() -> Vec<String> {
    let mut labels: Vec<String> = Vec::new();
    for task in eamadm::paper::PaperTask::ALL {
        for method in task.config().methods {
            if !labels.contains(&method.label) {
                labels.push(method.label);
            }
        }
    }
    labels
}

/// Arguments that cannot work.
#[derive(Debug, Error)]
pub(crate) enum ArgumentError {
    /// A `--method` label no config defines.
    #[error("--method {method:?}: unknown method; the methods are: {}", known.join(", "))]
    UnknownMethod {
        /// The label given.
        method: String,
        /// The labels that exist.
        known: Vec<String>,
    },
    /// An `--out` folder inside the fixtures.
    #[error(
        "--out {}: the output folder must not be inside {} (fixtures are written only by \
         `cargo xtask regen-fixtures`); choose another folder or omit --out for the default \
         target/reproduce-paper",
        out.display(),
        fixtures.display()
    )]
    OutInsideFixtures {
        /// The resolved output folder.
        out: PathBuf,
        /// The workspace's fixtures folder.
        fixtures: PathBuf,
    },
    /// A `--pretrained-cache` inside the output folder.
    #[error(
        "--pretrained-cache {}: the cache must not be inside the output folder {} (it is shared \
         by output folders and would make the output large); choose another folder or omit \
         --pretrained-cache for the default target/pretrained-cache",
        cache.display(),
        out.display()
    )]
    CacheInsideOut {
        /// The resolved cache folder.
        cache: PathBuf,
        /// The resolved output folder.
        out: PathBuf,
    },
    /// An `--out` that exists and is not a folder.
    #[error("--out {}: exists and is not a folder", out.display())]
    OutNotAFolder {
        /// The resolved output folder.
        out: PathBuf,
    },
    /// An `--out` below something that exists and is not a folder (`some-file/sub`).
    #[error(
        "--out {}: {} exists and is not a folder, so the output folder cannot be made there; \
         choose another --out",
        out.display(),
        blocker.display()
    )]
    OutUnderAFile {
        /// The resolved output folder.
        out: PathBuf,
        /// The existing non-folder on its path.
        blocker: PathBuf,
    },
}

/// Where the workspace is and where the command was started: relative paths given on the
/// command line are relative to `current_dir`, default outputs to `root`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Workspace {
    /// The workspace root (the folder of the root `Cargo.toml`).
    pub(crate) root: PathBuf,
    /// The folder the command was started in.
    pub(crate) current_dir: PathBuf,
}

impl Workspace {
    /// The workspace this xtask was built in, and the process's current folder.
    pub(crate) fn from_env() -> io::Result<Self> {
        // xtask/ sits directly under the workspace root.
        let manifest_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
        let root = manifest_dir.parent().unwrap_or(manifest_dir).to_path_buf();
        Ok(Self {
            root,
            current_dir: std::env::current_dir()?,
        })
    }

    /// `fixtures/` of the workspace.
    pub(crate) fn fixtures(&self) -> PathBuf {
        self.root.join("fixtures")
    }

    /// The default output folder, `target/reproduce-paper` under the root.
    pub(crate) fn default_out(&self) -> PathBuf {
        self.root.join("target").join("reproduce-paper")
    }

    /// The build folder cargo uses: `CARGO_TARGET_DIR` (a relative one taken from the folder
    /// the command was started in, as cargo takes it) or the workspace's `target/`. The Python
    /// tooling keeps its virtualenvs and wheels there.
    pub(crate) fn target_dir(&self) -> PathBuf {
        target_dir_of(
            std::env::var_os("CARGO_TARGET_DIR").as_deref(),
            &self.root,
            &self.current_dir,
        )
    }

    /// The default cache of pre-trained artefacts, `target/pretrained-cache` under the root
    /// (beside the default output folder, whatever `CARGO_TARGET_DIR` says).
    pub(crate) fn default_pretrained_cache(&self) -> PathBuf {
        self.root.join("target").join("pretrained-cache")
    }
}

/// [`Workspace::target_dir`] for the value `variable` of `CARGO_TARGET_DIR`.
fn target_dir_of(variable: Option<&std::ffi::OsStr>, root: &Path, current_dir: &Path) -> PathBuf {
    match variable {
        Some(dir) if !dir.is_empty() => current_dir.join(dir),
        _ => root.join("target"),
    }
}

/// A checked `reproduce-paper` invocation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ReproducePlan {
    /// Tasks to run, in run order, without repeats.
    pub(crate) tasks: Vec<PaperTask>,
    /// Method labels to run, in the order given (or the config's order), without repeats.
    pub(crate) methods: Vec<String>,
    /// Seeds per task and method.
    pub(crate) seeds: u32,
    /// Smoke run: few seeds and episodes.
    pub(crate) quick: bool,
    /// Config file replacing the embedded defaults.
    pub(crate) config: Option<PathBuf>,
    /// Absolute output folder.
    pub(crate) out: PathBuf,
    /// Which readings of the paper are rerun besides the presets.
    pub(crate) readings: Readings,
    /// The absolute folder of the pre-trained artefacts (outside `out`).
    pub(crate) pretrained_cache: PathBuf,
}

impl ReproducePlan {
    /// Checks `args`: method labels against `known_methods` (the labels the config defines),
    /// the config file is readable (a regular file of at most 1 MiB), the output folder is not
    /// inside `fixtures/`, is a folder if it exists, and has only folders on its path.
    /// Touches nothing on disk.
    pub(crate) fn from_args(
        args: &ReproduceArgs,
        known_methods: &[String],
        workspace: &Workspace,
    ) -> Result<Self, ArgumentError> {
        let tasks = if args.tasks.is_empty() {
            PaperTask::ALL.to_vec()
        } else {
            let mut tasks = args.tasks.clone();
            tasks.sort_unstable();
            tasks.dedup();
            tasks
        };

        let mut methods: Vec<String> = Vec::new();
        if args.methods.is_empty() {
            methods.extend_from_slice(known_methods);
        }
        for method in &args.methods {
            if !known_methods.contains(method) {
                return Err(ArgumentError::UnknownMethod {
                    method: method.clone(),
                    known: known_methods.to_vec(),
                });
            }
            if !methods.contains(method) {
                methods.push(method.clone());
            }
        }

        // The file is read once, by `experiments::load_config_file`, before anything runs.
        let config = args
            .config
            .as_ref()
            .map(|path| workspace.current_dir.join(path));

        let out = match &args.out {
            None => workspace.default_out(),
            Some(out) => lexically_normal(&workspace.current_dir.join(out)),
        };
        let fixtures = workspace.fixtures();
        if resolve_links(&out).starts_with(resolve_links(&fixtures)) {
            return Err(ArgumentError::OutInsideFixtures { out, fixtures });
        }
        if out.exists() && !out.is_dir() {
            return Err(ArgumentError::OutNotAFolder { out });
        }
        // The folder will be created: everything on its path that exists must be a folder.
        if let Some(blocker) = out
            .ancestors()
            .skip(1)
            .find(|ancestor| ancestor.exists() && !ancestor.is_dir())
        {
            return Err(ArgumentError::OutUnderAFile {
                blocker: blocker.to_path_buf(),
                out,
            });
        }

        let pretrained_cache = match &args.pretrained_cache {
            None => workspace.default_pretrained_cache(),
            Some(cache) => lexically_normal(&workspace.current_dir.join(cache)),
        };
        if resolve_links(&pretrained_cache).starts_with(resolve_links(&out)) {
            return Err(ArgumentError::CacheInsideOut {
                cache: pretrained_cache,
                out,
            });
        }

        Ok(Self {
            tasks,
            methods,
            seeds: args.seeds.unwrap_or(if args.quick {
                QUICK_SEEDS
            } else {
                // The default run's: the presets' seeds.
                eamadm::paper::seeds()
            }),
            quick: args.quick,
            config,
            pretrained_cache,
            out,
            readings: args.readings,
        })
    }

    /// Number of experiments: the one of a `--config` file, or one per selected task.
    pub(crate) fn experiments(&self) -> usize {
        if self.config.is_some() {
            1
        } else {
            self.tasks.len()
        }
    }

    /// Number of runs: experiments × methods × seeds (an upper bound when an experiment's
    /// config lacks some of the methods, as the robot's lacks the maze controls).
    pub(crate) fn runs(&self) -> u64 {
        self.experiments() as u64 * self.methods.len() as u64 * u64::from(self.seeds)
    }

    /// The plan, for people.
    pub(crate) fn describe(&self) -> String {
        let mut text = String::from("reproduce-paper plan\n");
        let tasks: Vec<String> = self
            .tasks
            .iter()
            .map(|t| format!("{} ({})", t.name(), t.description()))
            .collect();
        // Writing to a String cannot fail.
        if self.config.is_some() {
            let _ = writeln!(text, "  tasks:    the one the config file names");
        } else {
            let _ = writeln!(text, "  tasks:    {}", tasks.join(", "));
        }
        let _ = writeln!(text, "  methods:  {}", self.methods.join(", "));
        let _ = writeln!(
            text,
            "  seeds:    {} per task and method → at most {} × {} × {} = {} runs (each task runs \
             the methods its config defines){}",
            self.seeds,
            self.experiments(),
            self.methods.len(),
            self.seeds,
            self.runs(),
            if self.quick {
                " (quick: few episodes)"
            } else {
                ""
            }
        );
        let config = self.config.as_ref().map_or_else(
            || "embedded defaults (the paper's Table 1 and 2)".to_owned(),
            |path| path.display().to_string(),
        );
        let _ = writeln!(text, "  config:   {config}");
        if self.readings == Readings::None {
            let _ = writeln!(
                text,
                "  readings: off (--readings none): only the presets' experiments run; \
                 sensitivity.csv has only its header, the report no sensitivity section, and its \
                 verdict table says \"not run\" under the readings"
            );
        }
        let _ = writeln!(
            text,
            "  output:   {} (runs/ store, CSV curves, final-scores.csv, claims.csv, SVG figures, REPORT.md)",
            self.out.display()
        );
        text
    }
}

/// The `regen-fixtures` plan, for people.
pub(crate) fn describe_regen_fixtures(check: bool, workspace: &Workspace) -> String {
    let fixtures = workspace.fixtures();
    let mut text = String::from("regen-fixtures plan\n");
    let action = if check {
        "compare with what the code produces now, writing nothing; fail naming the first file \
         that differs"
    } else {
        "regenerate"
    };
    let _ = writeln!(text, "  fixtures: {}", fixtures.display());
    let _ = writeln!(text, "  action:   {action}");
    let _ = writeln!(
        text,
        "  files:    maze layouts (task1, task2, aggregation-control), the robot scenario, and reference trajectories \
         and curves for one fixed seed per task and method, each with a header saying how it \
         was made"
    );
    text
}

/// `path` with `.` removed and `..` applied, without touching the file system.
fn lexically_normal(path: &Path) -> PathBuf {
    let mut normal = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                // `..` at the root stays at the root; a leading `..` of a relative path stays.
                if !normal.pop() && !normal.has_root() {
                    normal.push(component);
                }
            }
            other => normal.push(other),
        }
    }
    normal
}

/// `path` with symbolic links resolved in the part that exists (the rest may not exist yet), so
/// that a link into `fixtures/` is recognised.
fn resolve_links(path: &Path) -> PathBuf {
    let mut existing = path;
    let mut rest = Vec::new();
    loop {
        if let Ok(canonical) = existing.canonicalize() {
            return rest
                .iter()
                .rev()
                .fold(canonical, |acc: PathBuf, part| acc.join(part));
        }
        match (existing.parent(), existing.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_owned());
                existing = parent;
            }
            _ => return path.to_path_buf(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_target_dir_follows_cargo_target_dir() {
        let (root, here) = (Path::new("/ws"), Path::new("/elsewhere"));
        assert_eq!(target_dir_of(None, root, here), Path::new("/ws/target"));
        assert_eq!(
            target_dir_of(Some("".as_ref()), root, here),
            Path::new("/ws/target")
        );
        assert_eq!(
            target_dir_of(Some("/tmp/t".as_ref()), root, here),
            Path::new("/tmp/t")
        );
        assert_eq!(
            target_dir_of(Some("build".as_ref()), root, here),
            Path::new("/elsewhere/build")
        );
    }

    #[test]
    fn the_regen_fixtures_plan_reads_well() {
        let ws = Workspace {
            root: PathBuf::from("/nonexistent-ws"),
            current_dir: PathBuf::from("/nonexistent-ws"),
        };
        insta::assert_snapshot!("regen_check", describe_regen_fixtures(true, &ws));
    }

    #[test]
    fn lexical_normalisation() {
        assert_eq!(
            lexically_normal(Path::new("/a/./b/../c/")),
            PathBuf::from("/a/c")
        );
        assert_eq!(lexically_normal(Path::new("/..")), PathBuf::from("/"));
    }
}
