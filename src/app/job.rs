//! Background jobs: long work runs on a worker thread with a shared [`Progress`] (fraction and
//! cancel flag); the UI thread polls for the result and never blocks.

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

impl<T: Send + 'static> Job<T> {
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
}
