//! Writing results to standard output without panicking.
//!
//! `println!` panics when stdout is closed early (`wildlod info x --json |
//! head`). A closed pipe means the reader has all it wants, so, like other
//! command-line tools, wildlod stops writing quietly; any other write error
//! is reported.

use std::io::{ErrorKind, Write};

/// Writes `text` to standard output and flushes it.
pub fn emit(text: &str) -> anyhow::Result<()> {
    write_to(&mut std::io::stdout().lock(), text)
}

fn write_to(out: &mut impl Write, text: &str) -> anyhow::Result<()> {
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != ErrorKind::BrokenPipe => {
            Err(anyhow::Error::new(e).context("cannot write to standard output"))
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer that fails every write with `kind`.
    struct Failing(ErrorKind);

    impl Write for Failing {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(self.0.into())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_closed_pipe_ends_the_output_quietly() {
        assert!(write_to(&mut Failing(ErrorKind::BrokenPipe), "x").is_ok());
    }

    #[test]
    fn other_write_errors_are_reported() {
        let e = write_to(&mut Failing(ErrorKind::StorageFull), "x").unwrap_err();
        assert!(format!("{e:#}").contains("standard output"), "{e:#}");
    }

    #[test]
    fn text_is_written_whole() {
        let mut v = Vec::new();
        write_to(&mut v, "a\nb\n").unwrap();
        assert_eq!(v, b"a\nb\n");
    }
}
