//! The command's logger: Kea's warnings (singular systems, pivoting caps, quarantined islands,
//! failed collision pairs) printed on stderr, each kind once, with how many more of it came at
//! the end. A kind is a message with its numbers left out, so "step 12: island of 2 bodies"
//! and "step 40: island of 3 bodies" count together.
//!
//! The level is `warn` unless `KEA_LOG` says `off`, `error`, `warn`, `info`, `debug` or `trace`.
//! (`env_logger` prints every message; a run of 600 steps with a redundant joint would print
//! 600 lines, so the command keeps its own.)

use log::{Level, LevelFilter, Log, Metadata, Record};
use std::sync::Mutex;

/// Messages seen so far: kind, how many times, the first message in full.
struct Seen {
    kinds: Vec<(String, u64)>,
}

struct Logger {
    seen: Mutex<Seen>,
}

static LOGGER: Logger = Logger {
    seen: Mutex::new(Seen { kinds: Vec::new() }),
};

/// A message's kind: its text with every run of digits (and a number's point or sign) as `#`.
fn kind(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut in_number = false;
    for c in message.chars() {
        let numeric = c.is_ascii_digit() || (in_number && matches!(c, '.' | 'e' | '-'));
        if numeric {
            if !in_number {
                out.push('#');
            }
        } else {
            out.push(c);
        }
        in_number = numeric;
    }
    out
}

impl Log for Logger {
    fn enabled(&self, metadata: &Metadata) -> bool {
        metadata.level() <= log::max_level()
    }

    fn log(&self, record: &Record) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let message = record.args().to_string();
        let key = kind(&message);
        let Ok(mut seen) = self.seen.lock() else {
            return;
        };
        match seen.kinds.iter_mut().find(|(k, _)| *k == key) {
            Some((_, count)) => *count += 1,
            None => {
                seen.kinds.push((key, 1));
                let level = match record.level() {
                    Level::Error => "error",
                    Level::Warn => "warning",
                    Level::Info => "info",
                    Level::Debug => "debug",
                    Level::Trace => "trace",
                };
                eprintln!("{level}: {message}");
            }
        }
    }

    fn flush(&self) {}
}

/// Installs the logger at the level `KEA_LOG` asks for (default `warn`).
pub fn install() {
    let level = match std::env::var("KEA_LOG").as_deref().map(str::to_lowercase) {
        Ok(s) if s == "off" => LevelFilter::Off,
        Ok(s) if s == "error" => LevelFilter::Error,
        Ok(s) if s == "info" => LevelFilter::Info,
        Ok(s) if s == "debug" => LevelFilter::Debug,
        Ok(s) if s == "trace" => LevelFilter::Trace,
        _ => LevelFilter::Warn,
    };
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(level);
    }
}

/// Prints how many more of each kind came after its first message; the kinds with one
/// message were said in full already.
pub fn report_repeats() {
    let Ok(seen) = LOGGER.seen.lock() else {
        return;
    };
    for (key, count) in seen.kinds.iter().filter(|(_, n)| *n > 1) {
        eprintln!("  … and {} more like: {key}", count - 1);
    }
}

#[cfg(test)]
mod tests {
    use super::kind;

    #[test]
    fn numbers_do_not_make_a_new_kind() {
        assert_eq!(
            kind("kea: step 12: island of 2 bodies (1.5e-3)"),
            kind("kea: step 407: island of 31 bodies (2.25e4)")
        );
        assert_ne!(
            kind("kea: LCP pivoting cycle"),
            kind("kea: singular system")
        );
    }
}
