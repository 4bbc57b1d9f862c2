//! The message log (bottom panel) and the notifications (toasts) shown over the viewport.

use crate::diagnostics::Severity;

/// One logged message.
#[derive(Clone, Debug, PartialEq)]
pub struct LogEntry {
    /// Seconds since the workstation started.
    pub time_s: f64,
    /// How serious.
    pub severity: Severity,
    /// The message (file and place included where known).
    pub text: String,
}

/// A notification shown over the viewport for a while.
#[derive(Clone, Debug, PartialEq)]
pub struct Toast {
    /// How serious.
    pub severity: Severity,
    /// The message.
    pub text: String,
    /// Seconds since start when it disappears.
    pub until_s: f64,
}

/// How long a notification stays, seconds.
const TOAST_S: f64 = 8.0;

/// Every message of this session, plus the notifications currently shown.
#[derive(Clone, Debug, Default)]
pub struct MessageLog {
    /// All entries, oldest first.
    pub entries: Vec<LogEntry>,
    /// Notifications on screen.
    pub toasts: Vec<Toast>,
}

impl MessageLog {
    /// Log a message.
    pub fn push(&mut self, time_s: f64, severity: Severity, text: impl Into<String>) {
        self.entries.push(LogEntry {
            time_s,
            severity,
            text: text.into(),
        });
    }

    /// Log a message and also show it as a notification.
    pub fn notify(&mut self, time_s: f64, severity: Severity, text: impl Into<String>) {
        let text = text.into();
        self.toasts.push(Toast {
            severity,
            text: text.clone(),
            until_s: time_s + TOAST_S,
        });
        self.push(time_s, severity, text);
    }

    /// Drop notifications whose time is up.
    pub fn expire(&mut self, now_s: f64) {
        self.toasts.retain(|t| t.until_s > now_s);
    }

    /// How many entries have at least this severity.
    #[must_use]
    pub fn count_at_least(&self, severity: Severity) -> usize {
        self.entries
            .iter()
            .filter(|e| e.severity >= severity)
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notifications_expire_but_stay_logged() {
        let mut log = MessageLog::default();
        log.notify(1.0, Severity::Error, "bad file");
        log.push(2.0, Severity::Info, "hello");
        assert_eq!(log.toasts.len(), 1);
        log.expire(1.0 + TOAST_S + 0.1);
        assert!(log.toasts.is_empty());
        assert_eq!(log.entries.len(), 2);
        assert_eq!(log.count_at_least(Severity::Warning), 1);
    }
}
