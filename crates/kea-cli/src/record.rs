//! Trajectories for `--csv` and `--json`: every body's pose and velocity after every step.

use kea::Real;
use kea_scene::BuiltScene;
use std::fmt::Write;

/// One body at one time: t, body index, position, orientation (x, y, z, w), velocity.
type Sample = (Real, usize, [Real; 3], [Real; 4], [Real; 3]);

/// Collects samples when asked to.
pub struct Recorder {
    on: bool,
    names: Vec<String>,
    samples: Vec<Sample>,
}

impl Recorder {
    /// A recorder that keeps samples only when `on`.
    pub fn new(on: bool) -> Self {
        Self {
            on,
            names: Vec::new(),
            samples: Vec::new(),
        }
    }

    /// Records every body at time `t`.
    pub fn capture(&mut self, t: Real, built: &BuiltScene) {
        if !self.on {
            return;
        }
        if self.names.is_empty() {
            self.names = built.bodies.iter().map(|(n, _)| n.clone()).collect();
        }
        for (i, (_, h)) in built.bodies.iter().enumerate() {
            if let Ok(b) = built.world.body(*h) {
                let (p, q, v) = (b.position(), b.orientation(), b.linear_velocity());
                self.samples
                    .push((t, i, p.to_array(), q.to_array(), v.to_array()));
            }
        }
    }

    /// `t,body,x,y,z,qx,qy,qz,qw,vx,vy,vz`, one line per body per step.
    pub fn csv(&self) -> String {
        let mut out = String::from("t,body,x,y,z,qx,qy,qz,qw,vx,vy,vz\n");
        for (t, i, p, q, v) in &self.samples {
            let _ = writeln!(
                out,
                "{t},{},{},{},{},{},{},{},{},{},{},{}",
                self.names[*i], p[0], p[1], p[2], q[0], q[1], q[2], q[3], v[0], v[1], v[2]
            );
        }
        out
    }

    /// `[{"t": …, "body": …, "position": […], "orientation": […], "velocity": […]}, …]`.
    pub fn json(&self) -> String {
        let rows: Vec<serde_json::Value> = self
            .samples
            .iter()
            .map(|(t, i, p, q, v)| {
                serde_json::json!({
                    "t": t, "body": self.names[*i], "position": p, "orientation": q, "velocity": v
                })
            })
            .collect();
        let mut text = serde_json::to_string(&rows).expect("numbers and strings serialise");
        text.push('\n');
        text
    }
}
