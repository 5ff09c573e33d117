//! One place builds what a run's report needs of an experiment: its facts
//! ([`ExperimentFacts`]: episodes, seeds, γ, methods with their roles and control families,
//! the paper's figures, the robot's behaviour and reward readings, the equivalence margins)
//! and its runs' final scores, gathered run by run ([`ReportFacts`]) so that the main job,
//! which streams its runs from the store, and the Python package, which holds them, make the
//! same facts. [`Experiment::report_facts`] is the one-call form.
//!
//! ```
//! use eamadm::{Experiment, paper};
//!
//! let mut config = paper::task1();
//! config.methods.retain(|spec| ["ea-madm", "softmax"].contains(&spec.label.as_str()));
//! config.seeds = 1;
//! config.episodes = 4;
//! config.trajectories.episodes.clear();
//! for spec in &mut config.methods {
//!     if let eamadm::Method::EaMadm(ea) = &mut spec.method {
//!         ea.pretrain.episodes = 4;
//!     }
//! }
//! let experiment = Experiment::new(config)?;
//! let records = experiment.run_all()?;
//! let (facts, scores) = experiment.report_facts(&records)?;
//! assert_eq!((facts.name.as_str(), facts.title.as_str()), ("task1", "Task I"));
//! assert_eq!(facts.methods.len(), 2);
//! assert_eq!(scores.len(), 2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::behaviour::BehaviourAccumulator;
use crate::facts::ExperimentFacts;
use crate::record::RunRecord;
use crate::runner::Experiment;
use crate::scores::{self, FinalScore, ScoresError};

/// The report's facts of one experiment and its runs' final scores, gathered run by run in
/// job order: each run adds its final scores and, on the robot, its behaviour, and is not
/// held.
#[derive(Debug)]
pub struct ReportFacts<'a> {
    experiment: &'a Experiment,
    facts: ExperimentFacts,
    behaviour: Option<BehaviourAccumulator>,
    /// The runs' final scores, or the first run whose scores failed.
    scores: Result<Vec<FinalScore>, ScoresError>,
    /// The seeds of the runs pushed, each once.
    seeds: Vec<u64>,
    /// The methods of the runs pushed, in the order they came (job order).
    methods: Vec<String>,
}

impl<'a> ReportFacts<'a> {
    /// The facts of `experiment`, written under the folder `name` (its title is the paper
    /// task's when `name` is one, else `name`), with no run yet.
    #[must_use]
    pub fn new(experiment: &'a Experiment, name: &str) -> Self {
        let config = experiment.config();
        let mut facts =
            crate::paper::experiment_facts(name, &crate::paper::experiment_title(name), config);
        facts.reward_references = crate::diagnosis::reward_references(experiment);
        facts.margins = experiment.task().equivalence_margins();
        Self {
            experiment,
            facts,
            behaviour: experiment
                .task()
                .scenario()
                .is_some()
                .then(BehaviourAccumulator::default),
            scores: Ok(Vec::new()),
            seeds: Vec::new(),
            methods: Vec::new(),
        }
    }

    /// The facts so far: the experiment's (its methods, the paper's figures, …), without the
    /// runs' behaviour.
    #[must_use]
    pub fn facts(&self) -> &ExperimentFacts {
        &self.facts
    }

    /// Adds one run: its final scores and, on the robot, its behaviour.
    pub fn push(&mut self, record: &RunRecord) {
        if let Some(behaviour) = &mut self.behaviour {
            behaviour.push(record);
        }
        if !self.seeds.contains(&record.seed) {
            self.seeds.push(record.seed);
        }
        if !self.methods.contains(&record.method) {
            self.methods.push(record.method.clone());
        }
        if let Ok(rows) = &mut self.scores {
            match scores::final_score_of(record, self.experiment) {
                Ok(row) => rows.push(row),
                Err(error) => self.scores = Err(error),
            }
        }
    }

    /// The facts (the robot's behaviour summed, the seeds those of the runs pushed, or the
    /// config's without runs, and the methods in the order their runs came, the job order,
    /// then those not run) and the runs' final scores, in the order pushed.
    ///
    /// # Errors
    /// The [`ScoresError`] of the first run whose final scores could not be computed.
    pub fn finish(self) -> Result<(ExperimentFacts, Vec<FinalScore>), ScoresError> {
        let mut facts = self.facts;
        if let Some(behaviour) = self.behaviour {
            facts.behaviour = behaviour.finish();
        }
        if let Ok(seeds) = u32::try_from(self.seeds.len())
            && seeds > 0
        {
            facts.seeds = seeds;
        }
        let order = |label: &str| {
            self.methods
                .iter()
                .position(|m| m == label)
                .unwrap_or(usize::MAX)
        };
        facts.methods.sort_by_key(|m| order(&m.label));
        Ok((facts, self.scores?))
    }
}

impl Experiment {
    /// The report's facts of this experiment (under its config's name) and the final scores
    /// of `records`, its runs in job order: what [`ReportFacts`] gathers, in one call.
    ///
    /// # Errors
    /// The [`ScoresError`] of the first run whose final scores could not be computed.
    pub fn report_facts(
        &self,
        records: &[RunRecord],
    ) -> Result<(ExperimentFacts, Vec<FinalScore>), ScoresError> {
        let mut facts = ReportFacts::new(self, &self.config().name);
        for record in records {
            facts.push(record);
        }
        facts.finish()
    }
}

#[cfg(test)]
mod tests {
    use crate::{Experiment, Method, paper};

    /// The robot's report facts carry its reward diagnosis and behaviour, whoever gathers
    /// them (the Python package's reports lacked the diagnosis when it gathered its own), and
    /// the one-call form equals the run-by-run one.
    #[test]
    fn the_robots_facts_carry_the_reward_diagnosis_and_behaviour() {
        let mut config = paper::robot();
        config
            .methods
            .retain(|spec| ["ea-madm", "softmax"].contains(&spec.label.as_str()));
        config.seeds = 1;
        config.episodes = 2;
        config.trajectories.episodes.clear();
        for spec in &mut config.methods {
            if let Method::EaMadm(ea) = &mut spec.method {
                ea.pretrain.episodes = 2;
            }
        }
        let experiment = Experiment::new(config).unwrap();
        let records = experiment.run_all().unwrap();
        let (facts, scores) = experiment.report_facts(&records).unwrap();
        assert!(!facts.reward_references.is_empty());
        assert!(
            facts.reward_references[0]
                .methods
                .iter()
                .any(|m| m == "ea-madm")
        );
        assert_eq!(facts.behaviour.len(), 2);
        assert!(!facts.margins.is_empty());
        assert_eq!((facts.seeds, scores.len()), (1, 2));
        assert_eq!(facts.title, "Robot");
        let mut gathered = super::ReportFacts::new(&experiment, "robot");
        for record in &records {
            gathered.push(record);
        }
        assert_eq!(gathered.finish().unwrap(), (facts, scores));
    }
}
