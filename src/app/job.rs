//! Background jobs: long work runs on a worker thread with a shared [`Progress`] (fraction and
//! cancel flag); the UI thread polls for the result and never blocks.
//!
//! - [`Job`]: one running piece of work. Start it with [`Job::spawn`] (or [`Job::start`], which
//!   wakes the UI when the work ends), [`Job::poll`] it for the result, [`Job::cancel`] it, or
//!   drop it: a dropped job is cancelled (its worker stops at its next progress check and its
//!   result is thrown away).
//! - [`JobSlot`]: the one running job of a feature (calculate, simulate, post, reduce, load, …)
//!   with the key of what it works on. Starting a new job replaces (and so cancels) the running
//!   one; [`JobSlot::poll`] hands back the finished job's key, label, wall time and result.

use std::sync::mpsc;
use std::time::Instant;

use crate::diagnostics::Progress;

/// A running job producing a `T`.
#[derive(Debug)]
pub struct Job<T> {
    /// What the job does, for the status bar (`Opening part.stp`).
    pub label: String,
    /// Progress and cancel flag shared with the worker.
    pub progress: Progress,
    /// When the job started.
    pub started: Instant,
    receiver: mpsc::Receiver<T>,
}

/// What polling a job found.
#[derive(Debug)]
pub enum JobPoll<T> {
    /// Still running.
    Running,
    /// Finished with this result.
    Done(T),
    /// The worker ended without a result (it panicked).
    Lost,
}

/// A job as the status bar shows it: label, fraction done, seconds running.
pub type JobStatus = (String, f64, f64);

impl<T: Send + 'static> Job<T> {
    /// Start `work` on a new thread and repaint `ctx` when it ends (so the result is collected
    /// at once).
    pub fn start(
        label: impl Into<String>,
        ctx: &egui::Context,
        work: impl FnOnce(&Progress) -> T + Send + 'static,
    ) -> Self {
        let ctx = ctx.clone();
        Self::spawn(label, work, move || ctx.request_repaint())
    }

    /// Start `work` on a new thread; `on_done` runs on the worker right after it finishes (use it
    /// to wake the UI, e.g. `egui::Context::request_repaint`).
    pub fn spawn(
        label: impl Into<String>,
        work: impl FnOnce(&Progress) -> T + Send + 'static,
        on_done: impl FnOnce() + Send + 'static,
    ) -> Self {
        let progress = Progress::new();
        let (sender, receiver) = mpsc::channel();
        let worker_progress = progress.clone();
        let label = label.into();
        let spawned = std::thread::Builder::new()
            .name(format!("talas job: {label}"))
            .spawn(move || {
                let result = work(&worker_progress);
                // The UI may have dropped the job (cancelled); then nobody wants the result.
                let _ = sender.send(result);
                on_done();
            });
        // When the thread cannot start, the sender is dropped and the job reports Lost.
        drop(spawned);
        Self {
            label,
            progress,
            started: Instant::now(),
            receiver,
        }
    }

    /// Has the job finished?
    pub fn poll(&self) -> JobPoll<T> {
        match self.receiver.try_recv() {
            Ok(v) => JobPoll::Done(v),
            Err(mpsc::TryRecvError::Empty) => JobPoll::Running,
            Err(mpsc::TryRecvError::Disconnected) => JobPoll::Lost,
        }
    }

    /// Ask the worker to stop (it notices at its next progress check).
    pub fn cancel(&self) {
        self.progress.cancel();
    }
}

impl<T> Job<T> {
    /// Seconds since the job started.
    #[must_use]
    pub fn elapsed_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// The job as the status bar shows it.
    #[must_use]
    pub fn status(&self) -> JobStatus {
        (
            self.label.clone(),
            self.progress.fraction(),
            self.elapsed_s(),
        )
    }
}

impl<T> Drop for Job<T> {
    /// A dropped job is cancelled: nobody can collect its result any more.
    fn drop(&mut self) {
        self.progress.cancel();
    }
}

/// A job that has ended, as [`JobSlot::poll`] hands it back.
#[derive(Debug)]
pub struct Finished<T, K> {
    /// What the job worked on (given to [`JobSlot::start`]).
    pub key: K,
    /// The job's label.
    pub label: String,
    /// Wall time from start to collection, s.
    pub elapsed_s: f64,
    /// The result; `None` when the worker ended without one (it panicked).
    pub result: Option<T>,
}

/// The (at most one) running job of a feature, with the key of what it works on.
#[derive(Debug)]
pub struct JobSlot<T, K = ()> {
    running: Option<(K, Job<T>)>,
}

impl<T, K> Default for JobSlot<T, K> {
    fn default() -> Self {
        Self { running: None }
    }
}

impl<T: Send + 'static, K> JobSlot<T, K> {
    /// Run `job` for `key`; a job still running is replaced, and so cancelled.
    pub fn start(&mut self, key: K, job: Job<T>) {
        self.running = Some((key, job));
    }

    /// Is a job running?
    #[must_use]
    pub fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// What the running job works on.
    #[must_use]
    pub fn key(&self) -> Option<&K> {
        self.running.as_ref().map(|(k, _)| k)
    }

    /// The running job.
    #[must_use]
    pub fn job(&self) -> Option<&Job<T>> {
        self.running.as_ref().map(|(_, j)| j)
    }

    /// The running job as the status bar shows it.
    #[must_use]
    pub fn status(&self) -> Option<JobStatus> {
        self.job().map(Job::status)
    }

    /// Cancel the running job; its label when there was one.
    pub fn cancel(&mut self) -> Option<String> {
        let (_, job) = self.running.take()?;
        job.cancel();
        Some(job.label.clone())
    }

    /// The finished job, once; `None` while it runs or when none was started.
    pub fn poll(&mut self) -> Option<Finished<T, K>> {
        let result = match self.job()?.poll() {
            JobPoll::Running => return None,
            JobPoll::Done(r) => Some(r),
            JobPoll::Lost => None,
        };
        let (key, job) = self.running.take()?;
        Some(Finished {
            key,
            label: job.label.clone(),
            elapsed_s: job.elapsed_s(),
            result,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wait<T: Send + 'static>(job: &Job<T>) -> JobPoll<T> {
        loop {
            match job.poll() {
                JobPoll::Running => std::thread::sleep(std::time::Duration::from_millis(1)),
                other => return other,
            }
        }
    }

    #[test]
    fn results_arrive_and_cancel_reaches_the_worker() {
        let job = Job::spawn("sum", |_| (1..=10).sum::<i32>(), || {});
        assert!(matches!(wait(&job), JobPoll::Done(55)));

        let (go, wait_go) = mpsc::channel::<()>();
        let job = Job::spawn(
            "cancellable",
            move |p| {
                let _ = wait_go.recv();
                p.is_cancelled()
            },
            || {},
        );
        job.cancel();
        let _ = go.send(());
        assert!(matches!(wait(&job), JobPoll::Done(true)));

        #[allow(clippy::panic)]
        let job: Job<()> = Job::spawn("panics", |_| panic!("worker failure"), || {});
        assert!(matches!(wait(&job), JobPoll::Lost));
    }

    #[test]
    fn a_dropped_or_replaced_job_is_cancelled() {
        let (go, wait_go) = mpsc::channel::<()>();
        let (seen, saw) = mpsc::channel::<bool>();
        let job = Job::spawn(
            "dropped",
            move |p| {
                let _ = wait_go.recv();
                let _ = seen.send(p.is_cancelled());
            },
            || {},
        );
        drop(job);
        let _ = go.send(());
        assert_eq!(saw.recv().ok(), Some(true));

        let mut slot: JobSlot<i32, &str> = JobSlot::default();
        let first = Job::spawn("first", |_| 1, || {});
        let first_progress = first.progress.clone();
        slot.start("a", first);
        slot.start("b", Job::spawn("second", |_| 2, || {}));
        assert!(first_progress.is_cancelled());
        assert_eq!(slot.key(), Some(&"b"));
        let finished = loop {
            if let Some(f) = slot.poll() {
                break f;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        };
        assert_eq!((finished.key, finished.label.as_str()), ("b", "second"));
        assert_eq!(finished.result, Some(2));
        assert!(!slot.is_running() && slot.poll().is_none());

        slot.start("c", Job::spawn("third", |_| 3, || {}));
        assert_eq!(slot.cancel().as_deref(), Some("third"));
        assert!(slot.cancel().is_none());
    }
}
