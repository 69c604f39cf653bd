//! The documentation every FMU carries: `documentation/index.html`, rendered by the FMU's
//! own binary (so the page and the binary cannot disagree) and packaged by `mechfmu build`.
//!
//! The page holds the mechanism's description, its equations and the notes on where it
//! departs from the course notes ([`Mechanism::NOTES`]), the variable table (units,
//! defaults, bounds, causality), the Co-Simulation capabilities and a plot of the default
//! experiment, run on the mechanism's [`Simulation`] (the steps `fmi2DoStep` takes) and
//! drawn as inline SVG. Everything is deterministic: the same source gives the same bytes.
//! The binary hands the page out through the `mechfmu_documentation` symbol
//! ([`export`](crate::export)).
//!
//! [`interface()`] renders the mechanism's interface (variables, default experiment, equations)
//! as a Markdown page instead, the one `mechfmu docs` writes to `docs/mechanisms/<Name>.md`
//! (symbol `mechfmu_interface`).

mod events;
mod interface;
mod notes;
mod svg;
mod tables;

pub use events::{events, events_for};

pub use interface::interface;

use crate::contract::{Version, CAPABILITIES};
use crate::model::{Causality, Layout, Mechanism, Variable};
use crate::simulation::{Simulation, StepFailure};
use std::fmt::Write as _;

/// The default experiment as run for the plot: times and the output variables' values.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    pub time: Vec<f64>,
    /// (variable, values at `time`), in value-reference order.
    pub signals: Vec<(&'static Variable, Vec<f64>)>,
    /// Why the run ended before the stop time, if it did.
    pub stopped: Option<String>,
}

/// Runs the default experiment of `M` on its simulation (start values as declared, inputs
/// at their start values, the steps `fmi2DoStep` takes) and records the states it outputs
/// (every output when it has no state) at every communication point.
pub fn default_experiment<M: Mechanism>() -> Result<Trajectory, String> {
    let e = M::EXPERIMENT;
    let mut sim = Simulation::<M>::new(Layout::new(M::VARIABLES)?);
    sim.setup(Some(e.tolerance), e.start)?;
    sim.update()
        .map_err(|m| format!("initialization failed: {m}"))?;
    // the states an importer sees (outputs with a derivative); every output if there are none
    let is_state = |v: &Variable| v.causality == Causality::Output && v.derivative.is_some();
    let any_state = M::VARIABLES.iter().any(is_state);
    let outputs: Vec<(u32, &'static Variable)> = M::VARIABLES
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            if any_state {
                is_state(v)
            } else {
                v.causality == Causality::Output
            }
        })
        .map(|(i, v)| (i as u32, v))
        .collect();
    let vrs: Vec<u32> = outputs.iter().map(|(vr, _)| *vr).collect();
    let mut row = vec![0.0; vrs.len()];
    let mut time = Vec::new();
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); vrs.len()];
    let mut record = |sim: &mut Simulation<M>, t: f64| -> Result<(), String> {
        sim.get_real(&vrs, &mut row)?;
        time.push(t);
        for (c, v) in columns.iter_mut().zip(&row) {
            c.push(*v);
        }
        Ok(())
    };
    record(&mut sim, e.start)?;
    let mut stopped = None;
    let n = ((e.stop - e.start) / e.step).round() as u64;
    for k in 0..n {
        let t = e.start + k as f64 * e.step;
        let h = (e.start + (k + 1) as f64 * e.step).min(e.stop) - t;
        match sim.step(t, h) {
            Ok(_) => record(&mut sim, t + h)?,
            Err(StepFailure::Rejected(message)) => return Err(message),
            Err(StepFailure::Stopped { time, message, .. }) => {
                stopped = Some(format!("stopped at t = {time}: {message}"));
                break;
            }
        }
    }
    Ok(Trajectory {
        time,
        signals: outputs.into_iter().map(|(_, v)| v).zip(columns).collect(),
        stopped,
    })
}

/// `documentation/index.html` of mechanism `M`'s FMI 2.0 FMU.
pub fn documentation<M: Mechanism>() -> Result<String, String> {
    page::<M>(Version::Fmi2)
}

/// `documentation/index.html` of mechanism `M`'s FMI 3.0 FMU: its variables as FMI 3.0
/// shows them (arrays, the independent time), its capabilities and calls.
pub fn documentation_fmi3<M: Mechanism>() -> Result<String, String> {
    page::<M>(Version::Fmi3)
}

fn page<M: Mechanism>(version: Version) -> Result<String, String> {
    let e = M::EXPERIMENT;
    let mut h = String::new();
    let name = escape(M::NAME);
    let (what, token) = match version {
        Version::Fmi2 => ("GUID", crate::contract::guid::<M>()),
        Version::Fmi3 => (
            "instantiation token",
            crate::contract::instantiation_token::<M>(),
        ),
    };
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{name}: {version} FMU</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n\
         <h1>{name}</h1>\n<p class=\"sub\">{version} FMU (Model Exchange and Co-Simulation) generated by mechfmu {} \
         &middot; {what} <code>{}</code></p>\n",
        env!("CARGO_PKG_VERSION"),
        escape(&token),
        version = version.name(),
    );
    h.push_str("<nav><a href=\"#description\">Description</a> &middot; <a href=\"#equations\">Equations and notes</a> &middot; \
                <a href=\"#events\">Events</a> &middot; <a href=\"#experiment\">Default experiment</a> &middot; <a href=\"#variables\">Variables</a> &middot; \
                <a href=\"#capabilities\">Capabilities</a> &middot; <a href=\"#files\">Files</a></nav>\n");

    h.push_str("<h2 id=\"description\">Description</h2>\n");
    h.push_str(&notes::render(M::DESCRIPTION));

    h.push_str("<h2 id=\"equations\">Equations and notes</h2>\n");
    if M::NOTES.trim().is_empty() {
        h.push_str("<p><em>The mechanism declares no notes.</em></p>\n");
    } else {
        h.push_str(&notes::render(M::NOTES));
    }

    h.push_str("<h2 id=\"events\">Events</h2>\n");
    h.push_str(&notes::render(&events_for::<M>(version)));

    h.push_str("<h2 id=\"experiment\">Default experiment</h2>\n");
    let _ = writeln!(
        h,
        "<p>Start {} s, stop {} s, communication step {} s, relative tolerance {} \
         (the <code>DefaultExperiment</code>); every parameter, start value and input at its \
         default. The curves below are this FMU's own states, recorded at every \
         communication point.</p>",
        num(e.start),
        num(e.stop),
        num(e.step),
        num(e.tolerance)
    );
    match default_experiment::<M>() {
        Ok(run) => {
            if let Some(why) = &run.stopped {
                let _ = writeln!(h, "<p class=\"warn\">The run {}</p>", escape(why));
            }
            h.push_str(&svg::plot(&run));
        }
        Err(e) => {
            let _ = writeln!(
                h,
                "<p class=\"warn\">The default experiment did not run: {}</p>",
                escape(&e)
            );
        }
    }

    h.push_str("<h2 id=\"variables\">Variables</h2>\n");
    match version {
        Version::Fmi2 => h.push_str(&tables::variable_table(M::VARIABLES)),
        Version::Fmi3 => h.push_str(&tables::fmi3_variable_table::<M>()?),
    }

    h.push_str("<h2 id=\"capabilities\">Capabilities</h2>\n");
    match version {
        Version::Fmi2 => h.push_str(&tables::capability_table(&CAPABILITIES)),
        Version::Fmi3 => h.push_str(&tables::fmi3_capability_table::<M>()),
    }

    h.push_str("<h2 id=\"files\">Files in this FMU</h2>\n<ul>\n");
    let _ = writeln!(
        h,
        "<li><code>modelDescription.xml</code>: the interface (generated from the same declaration as the binary)</li>\n\
         <li><code>binaries/</code>: the FMU's shared library, Model Exchange and Co-Simulation, for each platform \
         it was built for: <code>{linux}/{name}.so</code> (Linux x86-64), <code>{windows}/{name}.dll</code> \
         (Windows x86-64), <code>aarch64-linux/{name}.so</code> (Linux ARM 64-bit{arm_note})</li>\n\
         <li><code>documentation/index.html</code>: this page</li>\n\
         <li><code>extra/org.fmi-standard.fmi-ls-ref/</code> (when present): reference results of the default experiment \
         (<code>{name}_ref.csv</code>, with <code>{name}_in.csv</code> and <code>{name}_ref.opt</code> in the FMI \
         cross-check conventions), computed by an independent high-accuracy solution, not by this FMU</li>",
        linux = match version {
            Version::Fmi2 => "linux64",
            Version::Fmi3 => "x86_64-linux",
        },
        windows = match version {
            Version::Fmi2 => "win64",
            Version::Fmi3 => "x86_64-windows",
        },
        arm_note = match version {
            Version::Fmi2 => ", FMI 3.0's platform name, as FMI 2.0.5 directs for platforms FMI 2.0 does not name",
            Version::Fmi3 => "",
        },
    );
    h.push_str("</ul>\n</body>\n</html>\n");
    Ok(h)
}

const STYLE: &str = "body { font-family: system-ui, -apple-system, 'Segoe UI', sans-serif; max-width: 64rem; margin: 2rem auto; padding: 0 1rem; color: #1b1f24; line-height: 1.5; }
h1 { margin-bottom: 0.2rem; } h2 { border-bottom: 1px solid #d0d7de; padding-bottom: 0.2rem; margin-top: 2rem; }
.sub { color: #57606a; margin-top: 0; } nav { margin: 1rem 0; }
code, pre { font-family: ui-monospace, 'SFMono-Regular', Menlo, monospace; font-size: 0.92em; }
pre { background: #f6f8fa; padding: 0.6rem 0.8rem; overflow-x: auto; border-radius: 6px; }
table { border-collapse: collapse; font-size: 0.92em; } th, td { border: 1px solid #d0d7de; padding: 0.25rem 0.5rem; text-align: left; vertical-align: top; }
th { background: #f6f8fa; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
.warn { color: #9a6700; } svg { width: 100%; max-width: 60rem; height: auto; }
";

/// A number as Rust prints it (shortest round trip; exponent form when tiny or huge).
pub(crate) fn num(x: f64) -> String {
    if x.is_infinite() {
        if x > 0.0 {
            "&infin;".into()
        } else {
            "&minus;&infin;".into()
        }
    } else if x != 0.0 && !(1e-3..1e7).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// HTML escaping of text.
pub(crate) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests;
