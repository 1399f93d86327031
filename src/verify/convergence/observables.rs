//! What `rigidref converge` can measure ([`Observable`], the trace [`Field`]s) and against which
//! reference ([`ReferenceChoice`]); their spellings on the command line.

/// Speed below which a body counts as stopped, m/s: far below any scene's motion, above the
/// round-off of a body at rest on the ground (measured ≤ 1e-12).
pub const STOPPED: f64 = 1e-9;

/// What is measured from a run of one body (`--body`, default the first).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Observable {
    /// The time at which the body stops, s: the first step whose speed is below [`STOPPED`],
    /// refined by extending the line through the speeds of the last two steps before it to 0
    /// (exact under constant deceleration, O(dt²) otherwise) instead of reading it off the step
    /// grid (an O(dt) quantisation that says nothing about the scheme).
    StopTime,
    /// The horizontal (x–z) distance the body's centre of mass travelled until then, m.
    StopDistance,
    /// The first sign change of the body-frame spin about the intermediate principal axis (the
    /// Dzhanibekov flip), s, linearly interpolated between steps.
    FirstFlip,
    /// The first sign change of the world spin about the vertical ω_y (the rattleback's
    /// reversal), s, linearly interpolated between steps.
    FirstReversal,
    /// A state component at the end of `--time`.
    Final(Field),
}

/// A state component of a body: position (m), velocity (m/s) or world angular velocity (rad/s).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Field {
    /// Centre of mass x, m.
    X,
    /// Centre of mass y (up), m.
    Y,
    /// Centre of mass z, m.
    Z,
    /// Velocity x, m/s.
    Vx,
    /// Velocity y, m/s.
    Vy,
    /// Velocity z, m/s.
    Vz,
    /// World angular velocity about x, rad/s.
    Wx,
    /// World angular velocity about y, rad/s.
    Wy,
    /// World angular velocity about z, rad/s.
    Wz,
}

pub(super) const FIELDS: [(&str, Field); 9] = [
    ("x", Field::X),
    ("y", Field::Y),
    ("z", Field::Z),
    ("vx", Field::Vx),
    ("vy", Field::Vy),
    ("vz", Field::Vz),
    ("wx", Field::Wx),
    ("wy", Field::Wy),
    ("wz", Field::Wz),
];

/// The observables' names, as `--observable` takes them.
pub const OBSERVABLE_NAMES: &str = "stop_time, stop_distance, first_flip, first_reversal, \
     final_x, final_y, final_z, final_vx, final_vy, final_vz, final_wx, final_wy, final_wz";

impl std::str::FromStr for Observable {
    type Err = String;
    fn from_str(s: &str) -> Result<Observable, String> {
        let found = match s {
            "stop_time" => Some(Observable::StopTime),
            "stop_distance" => Some(Observable::StopDistance),
            "first_flip" => Some(Observable::FirstFlip),
            "first_reversal" => Some(Observable::FirstReversal),
            _ => s.strip_prefix("final_").and_then(|f| {
                FIELDS
                    .iter()
                    .find(|(name, _)| *name == f)
                    .map(|&(_, field)| Observable::Final(field))
            }),
        };
        found.ok_or_else(|| format!("unknown observable `{s}`; one of {OBSERVABLE_NAMES}"))
    }
}

impl std::fmt::Display for Observable {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Observable::StopTime => write!(f, "stop_time"),
            Observable::StopDistance => write!(f, "stop_distance"),
            Observable::FirstFlip => write!(f, "first_flip"),
            Observable::FirstReversal => write!(f, "first_reversal"),
            Observable::Final(field) => {
                let name = FIELDS.iter().find(|(_, x)| x == field).unwrap().0;
                write!(f, "final_{name}")
            }
        }
    }
}

impl Observable {
    /// The observable's unit.
    pub fn unit(&self) -> &'static str {
        match self {
            Observable::StopTime | Observable::FirstFlip | Observable::FirstReversal => "s",
            Observable::StopDistance => "m",
            Observable::Final(Field::X | Field::Y | Field::Z) => "m",
            Observable::Final(Field::Vx | Field::Vy | Field::Vz) => "m/s",
            Observable::Final(_) => "rad/s",
        }
    }
}

/// Which reference the errors are measured against.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReferenceChoice {
    /// The observable's own: the closed form for the stop, RK4 for the flip, the no-slip model
    /// for the reversal, Richardson extrapolation for a final value.
    Auto,
    /// v₀/(μg) and v₀²/(2μg) for a body sliding on the ground (cone friction, or box friction
    /// along a tangent axis), no load, no spin.
    ClosedForm,
    /// The torque-free Euler equations by RK4 (a body that touches nothing).
    Rk4,
    /// The ellipsoid rolling without slipping, by RK4 (a body with an `ellipsoid`).
    NoSlip,
    /// No reference: Richardson extrapolation of the runs.
    Richardson,
    /// A value given by the user (in the observable's unit).
    Value(f64),
}

impl std::str::FromStr for ReferenceChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<ReferenceChoice, String> {
        Ok(match s {
            "auto" => ReferenceChoice::Auto,
            "closed-form" => ReferenceChoice::ClosedForm,
            "rk4" => ReferenceChoice::Rk4,
            "no-slip" => ReferenceChoice::NoSlip,
            "richardson" => ReferenceChoice::Richardson,
            _ => match s.parse::<f64>() {
                Ok(v) if v.is_finite() => ReferenceChoice::Value(v),
                _ => {
                    return Err(format!(
                        "unknown reference `{s}`; one of auto, closed-form, rk4, no-slip, \
                         richardson, or a number"
                    ));
                }
            },
        })
    }
}
