//! Writing records on a thread of their own, so that formatting numbers (most of a trace's
//! cost besides the step) is not in the simulation loop. The records reach the output in the
//! order they were given, so the bytes are the same as writing them in place.

use std::io;
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

/// Records waiting for the writer thread before [`BackgroundWriter::write`] waits for it (a
/// bound, so that a slow disk holds the simulation back instead of filling memory).
pub const QUEUE: usize = 64;

enum Message<T> {
    Record(T),
    /// Flush the output and say how it went.
    Flush,
}

/// A writer thread that owns the output and writes each record given to it with `write_one`.
/// An error of the output is returned by the next [`BackgroundWriter::write`] or
/// [`BackgroundWriter::flush`]; records given after it are dropped.
pub struct BackgroundWriter<T: Send + 'static> {
    sender: Option<SyncSender<Message<T>>>,
    flushed: Receiver<io::Result<()>>,
    failure: Arc<Mutex<Option<io::Error>>>,
    worker: Option<JoinHandle<()>>,
}

impl<T: Send + 'static> BackgroundWriter<T> {
    /// Starts the thread; `flush` flushes the output.
    pub fn new<W: Send + 'static>(
        mut out: W,
        mut write_one: impl FnMut(&mut W, &T) -> io::Result<()> + Send + 'static,
        mut flush: impl FnMut(&mut W) -> io::Result<()> + Send + 'static,
    ) -> BackgroundWriter<T> {
        let (sender, receiver) = sync_channel::<Message<T>>(QUEUE);
        let (flushed_sender, flushed) = sync_channel(1);
        let failure = Arc::new(Mutex::new(None));
        let shared = failure.clone();
        let worker = std::thread::spawn(move || {
            let mut failed = false;
            for message in receiver {
                match message {
                    Message::Record(record) if !failed => {
                        if let Err(e) = write_one(&mut out, &record) {
                            failed = true;
                            *shared.lock().unwrap_or_else(|p| p.into_inner()) = Some(e);
                        }
                    }
                    Message::Record(_) => {}
                    Message::Flush => {
                        let result = if failed { Ok(()) } else { flush(&mut out) };
                        if flushed_sender.send(result).is_err() {
                            return;
                        }
                    }
                }
            }
            // The sender is gone: flush what was written (errors were or will be reported by
            // an explicit flush; a writer dropped without one ignores them, as `BufWriter` does).
            if !failed {
                let _ = flush(&mut out);
            }
        });
        BackgroundWriter {
            sender: Some(sender),
            flushed,
            failure,
            worker: Some(worker),
        }
    }

    /// The output's error, if the thread met one (taken: reported once).
    fn take_failure(&self) -> Option<io::Error> {
        self.failure
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take()
    }

    fn stopped() -> io::Error {
        io::Error::other("the trace writer thread stopped")
    }

    /// Queues one record (waits while [`QUEUE`] records are queued).
    pub fn write(&mut self, record: T) -> io::Result<()> {
        if let Some(e) = self.take_failure() {
            return Err(e);
        }
        let sender = self.sender.as_ref().ok_or_else(Self::stopped)?;
        sender
            .send(Message::Record(record))
            .map_err(|_| Self::stopped())
    }

    /// Waits until every record queued so far is written and the output flushed.
    pub fn flush(&mut self) -> io::Result<()> {
        let sender = self.sender.as_ref().ok_or_else(Self::stopped)?;
        sender.send(Message::Flush).map_err(|_| Self::stopped())?;
        let flushed = self.flushed.recv().map_err(|_| Self::stopped())?;
        match self.take_failure() {
            Some(e) => Err(e),
            None => flushed,
        }
    }
}

impl<T: Send + 'static> Drop for BackgroundWriter<T> {
    /// Writes what is queued and flushes, then ends the thread.
    fn drop(&mut self) {
        self.sender = None;
        if let Some(worker) = self.worker.take() {
            let _ = worker.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_arrive_in_order_and_a_failure_is_reported_once() {
        let out = Arc::new(Mutex::new(Vec::new()));
        let sink = out.clone();
        let mut w = BackgroundWriter::new(
            (),
            move |_, r: &u32| {
                if *r == 500 {
                    return Err(io::Error::other("disk full"));
                }
                sink.lock().unwrap().push(*r);
                Ok(())
            },
            |_| Ok(()),
        );
        for r in 0..200 {
            w.write(r).unwrap();
        }
        w.flush().unwrap();
        assert_eq!(*out.lock().unwrap(), (0..200).collect::<Vec<_>>());
        w.write(500).unwrap();
        // Reported by the flush, then not again; later records are dropped.
        assert!(w.flush().is_err());
        w.write(501).unwrap();
        w.flush().unwrap();
        assert_eq!(out.lock().unwrap().len(), 200);
    }
}
