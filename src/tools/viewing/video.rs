//! MP4 video through ffmpeg: frames are piped to `ffmpeg` as raw RGBA and encoded as H.264
//! (yuv420p, so that every player opens it; odd sizes padded by a pixel). ffmpeg must be on
//! the PATH; nothing is linked. docs/viewing.md §"Rendering".

use image::RgbaImage;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

/// An ffmpeg process writing one MP4 file from the frames given to it.
pub struct Mp4Writer {
    child: Option<Child>,
    stdin: Option<ChildStdin>,
    path: PathBuf,
    size: (u32, u32),
}

impl Mp4Writer {
    /// Starts ffmpeg writing `path` from frames of `width` × `height` pixels at `fps` frames
    /// per second.
    pub fn start(path: &Path, width: u32, height: u32, fps: f64) -> Result<Mp4Writer, String> {
        let mut child = Command::new("ffmpeg")
            .args([
                "-y",
                "-loglevel",
                "error",
                "-f",
                "rawvideo",
                "-pix_fmt",
                "rgba",
            ])
            .args(["-s", &format!("{width}x{height}")])
            .args(["-framerate", &format!("{fps:.6}")])
            .args(["-i", "-"])
            .args(["-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"])
            .args([
                "-c:v",
                "libx264",
                "-pix_fmt",
                "yuv420p",
                "-movflags",
                "+faststart",
            ])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| format!("{}: cannot start ffmpeg: {e}", path.display()))?;
        let stdin = child.stdin.take();
        Ok(Mp4Writer {
            child: Some(child),
            stdin,
            path: path.to_path_buf(),
            size: (width, height),
        })
    }

    /// Sends one frame (of the size given at the start).
    pub fn write(&mut self, img: &RgbaImage) -> Result<(), String> {
        if img.dimensions() != self.size {
            return Err(format!(
                "{}: frame of {}×{} pixels in a video of {}×{}",
                self.path.display(),
                img.width(),
                img.height(),
                self.size.0,
                self.size.1
            ));
        }
        let Some(stdin) = &mut self.stdin else {
            return Err(format!(
                "{}: the video is already finished",
                self.path.display()
            ));
        };
        if stdin.write_all(img.as_raw()).is_err() {
            // ffmpeg has exited: its own message says why.
            return Err(self.close());
        }
        Ok(())
    }

    /// Closes the stream and waits for ffmpeg to write the file.
    pub fn finish(mut self) -> Result<(), String> {
        match self.close() {
            e if e.is_empty() => Ok(()),
            e => Err(e),
        }
    }

    /// Closes ffmpeg's input and waits for it; returns its error message, empty on success.
    fn close(&mut self) -> String {
        self.stdin = None;
        let Some(child) = self.child.take() else {
            return String::new();
        };
        match child.wait_with_output() {
            Ok(out) if out.status.success() => String::new(),
            Ok(out) => format!(
                "{}: ffmpeg failed ({}): {}",
                self.path.display(),
                out.status,
                String::from_utf8_lossy(&out.stderr).trim()
            ),
            Err(e) => format!("{}: ffmpeg: {e}", self.path.display()),
        }
    }
}

impl Drop for Mp4Writer {
    /// A writer dropped early (a run that stopped) still closes the file properly.
    fn drop(&mut self) {
        let _ = self.close();
    }
}
