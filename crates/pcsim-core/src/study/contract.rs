//! The study contract (issue 52; MuJoCo's plugin table, OpenFAST's typed `InitInput`): every
//! study is one value that owns its spec (with its `Default` and its check), runs, and hands
//! back a typed output that is written and read back through the same type, the files it is
//! written as, and the answer its report and the terminal open with. A kind is one variant of
//! [`StudyKind`], matched exhaustively wherever studies are told apart (a manifest, the figures,
//! the report), so a study that forgets one of them does not compile. The front ends only drive
//! it (the CLI's `driver.rs`, Python's bindings).

use serde::{Deserialize, Serialize};

use crate::error::{CaseError, SimError};

/// Every kind of output directory pcsim writes, by the study that wrote it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum StudyKind {
    /// One run (`pcsim run`), with its evidence (`--verify`, `--sensitivity`).
    #[serde(rename = "run")]
    Run,
    /// Realisations over the seeds of a case's random inputs (`pcsim run --seeds`).
    #[serde(rename = "montecarlo")]
    MonteCarlo,
    /// The energy distribution and the EVA over a grid (`pcsim eva`).
    #[serde(rename = "eva")]
    Eva,
    /// The accuracy-based window length over a grid (`pcsim window`).
    #[serde(rename = "window")]
    Window,
    /// The real-time window against the full model (`pcsim realtime`).
    #[serde(rename = "realtime")]
    Realtime,
    /// A run beside a recording car's force (`pcsim compare`).
    #[serde(rename = "compare")]
    Compare,
    /// The design search (`pcsim design`).
    #[serde(rename = "design")]
    Design,
    /// A pantograph's frequency response at the head (`pcsim pantograph frf`).
    #[serde(rename = "pantograph-frf")]
    PantographFrf,
    /// A chain fitted to a measured response (`pcsim pantograph fit`).
    #[serde(rename = "pantograph-fit")]
    PantographFit,
    /// Current collection: arcing, wear, the lateral sweep, their life (`pcsim study wear`).
    #[serde(rename = "wear")]
    Wear,
}

impl StudyKind {
    /// Every kind, in a fixed order.
    pub const ALL: [StudyKind; 10] = [
        StudyKind::Run,
        StudyKind::MonteCarlo,
        StudyKind::Eva,
        StudyKind::Window,
        StudyKind::Realtime,
        StudyKind::Compare,
        StudyKind::Design,
        StudyKind::PantographFrf,
        StudyKind::PantographFit,
        StudyKind::Wear,
    ];

    /// Its name in a manifest (`pcsim.json`'s `kind`).
    pub fn name(self) -> &'static str {
        match self {
            StudyKind::Run => "run",
            StudyKind::MonteCarlo => "montecarlo",
            StudyKind::Eva => "eva",
            StudyKind::Window => "window",
            StudyKind::Realtime => "realtime",
            StudyKind::Compare => "compare",
            StudyKind::Design => "design",
            StudyKind::PantographFrf => "pantograph-frf",
            StudyKind::PantographFit => "pantograph-fit",
            StudyKind::Wear => "wear",
        }
    }

    /// The kind a manifest names (an unknown name is refused, naming the known ones).
    pub fn parse(name: &str) -> Result<StudyKind, CaseError> {
        StudyKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| CaseError::Invalid {
                field: "kind".into(),
                value: name.into(),
                reason: format!(
                    "not a kind of pcsim output: {}",
                    StudyKind::ALL.map(StudyKind::name).join(", ")
                ),
            })
    }
}

impl std::fmt::Display for StudyKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The answer a study's report and terminal open with: a headline, then named values (each
/// with its unit in the name), then what the answer does not establish. The driver writes it
/// as `answer.json` (`pcsim schema answer`), which the report opens with for any kind.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Answer {
    /// One sentence: what the study found.
    pub headline: String,
    /// The answer's values, `(what, value)`, in order.
    pub rows: Vec<(String, String)>,
    /// What the user should know but accepted (events allowed by a flag).
    pub warnings: Vec<String>,
    /// What makes the answer incomplete or refused (events not accepted, runs not made): a
    /// front end writes the outputs, then refuses the study with these.
    pub failures: Vec<String>,
}

/// A file of a study's output directory: its name and its bytes (the front end writes it).
#[derive(Debug, Clone, PartialEq)]
pub struct StudyFile {
    /// Its name in the output directory.
    pub name: String,
    /// Its bytes.
    pub bytes: Vec<u8>,
}

impl StudyFile {
    /// A text file.
    pub fn text(name: &str, text: String) -> Self {
        StudyFile {
            name: name.into(),
            bytes: text.into_bytes(),
        }
    }
}

/// A study: its spec and inputs in `self`, checked before any work, run, and its typed output
/// turned into the files of its output directory and the answer its report opens with.
pub trait Study {
    /// Its kind.
    const KIND: StudyKind;
    /// What it computes; written (`files`) and read back through this one type.
    type Output: Serialize + serde::de::DeserializeOwned;

    /// Refuse what the study cannot honour, by its field, before any run.
    fn check(&self) -> Result<(), CaseError>;

    /// Units of work (runs), for the progress line and the bound on the work.
    fn work(&self) -> usize;

    /// Run it; `done()` after each unit of work.
    fn run(&self, done: &(dyn Fn() + Sync)) -> Result<Self::Output, SimError>;

    /// The output directory's files (the manifest aside), in the order they are written.
    fn files(&self, output: &Self::Output) -> Vec<StudyFile>;

    /// The answer its report and terminal open with.
    fn answer(output: &Self::Output) -> Answer;

    /// Its figures as data (drawn by the front end as line charts, the same way for every
    /// study: `figures.json`); the studies that draw their own figures give none.
    fn figures(&self, _output: &Self::Output) -> Vec<Figure> {
        Vec::new()
    }

    /// The case it studies, for the manifest (a command that fills it itself gives none).
    fn case_label(&self) -> Option<CaseLabel> {
        None
    }
}

/// A figure a study declares as data: one x–y chart of named series (MuJoCo's rule: the engine
/// says what to show in model terms; the front end only draws it).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Figure {
    /// Its file name without the extension (`wear_profile`).
    pub name: String,
    /// Its title.
    pub title: String,
    /// The x axis' label, with its unit.
    pub x_label: String,
    /// The y axis' label, with its unit.
    pub y_label: String,
    /// Its series, drawn in order.
    pub series: Vec<FigureSeries>,
    /// A logarithmic y axis (values ≤ 0 left out).
    #[serde(default)]
    pub log_y: bool,
}

/// One series of a [`Figure`].
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FigureSeries {
    /// Its legend.
    pub label: String,
    /// Its x values.
    pub x: Vec<f64>,
    /// Its y values (as many as `x`).
    pub y: Vec<f64>,
    /// Drawn as dots (a scatter) instead of a line.
    #[serde(default)]
    pub dots: bool,
}

/// What a study's run gave, its output type erased: the files, the answer and the figures.
#[derive(Debug, Clone, PartialEq)]
pub struct Ran {
    /// The output directory's files, in order.
    pub files: Vec<StudyFile>,
    /// The answer.
    pub answer: Answer,
    /// The figures declared as data.
    pub figures: Vec<Figure>,
}

impl Ran {
    /// What `study`'s `output` is written as: its files, its answer, its figures.
    pub fn of<S: Study>(study: &S, output: &S::Output) -> Ran {
        Ran {
            files: study.files(output),
            answer: S::answer(output),
            figures: study.figures(output),
        }
    }
}

/// A study with its output type erased: what the registry of spec-file studies hands out
/// ([`crate::study::from_spec`]) and the one driver takes. Every [`Study`] is one.
pub trait AnyStudy: Sync {
    /// Its kind.
    fn kind(&self) -> StudyKind;
    /// [`Study::check`].
    fn check(&self) -> Result<(), CaseError>;
    /// [`Study::work`].
    fn work(&self) -> usize;
    /// [`Study::run`], then its files, answer and figures.
    fn run_erased(&self, done: &(dyn Fn() + Sync)) -> Result<Ran, SimError>;
    /// [`Study::case_label`].
    fn case_label(&self) -> Option<CaseLabel>;
}

/// What a manifest says of the case a study ran: its name, its speed (km/h) and its analysis
/// section (m).
pub type CaseLabel = (String, f64, [f64; 2]);

impl<S: Study + Sync> AnyStudy for S {
    fn kind(&self) -> StudyKind {
        S::KIND
    }
    fn check(&self) -> Result<(), CaseError> {
        Study::check(self)
    }
    fn work(&self) -> usize {
        Study::work(self)
    }
    fn case_label(&self) -> Option<CaseLabel> {
        Study::case_label(self)
    }
    fn run_erased(&self, done: &(dyn Fn() + Sync)) -> Result<Ran, SimError> {
        Ok(Ran::of(self, &self.run(done)?))
    }
}
