//! fmi2Instantiate with sane and hostile arguments (NULL or odd names, a wrong or NULL
//! GUID, an unknown or undeclared fmuType, NULL callbacks, no logger, hostile resource
//! locations, visible and loggingOn out of range).

use super::Fmi2;
use crate::ffi::*;
use crate::importer::{callbacks, Sink};
use crate::sequences::args::SANE_NAMES;
use crate::sequences::core::Sequence;
use crate::sequences::machine::{Inst, Kind};
use std::ffi::CString;

impl Sequence<'_, Fmi2> {
    pub(crate) fn instantiate(&mut self) {
        if self.insts.len() >= 2 {
            return;
        }
        let sink = Box::<Sink>::default();
        let mut cb = Box::new(callbacks(&sink));
        let hostile = self.rng.chance(0.15);
        let mut expect_null = false;
        let mut logs = true;
        if self.rng.chance(0.05) {
            cb.logger = None;
            logs = false;
        } else if self.rng.chance(0.03) {
            cb.componentEnvironment = std::ptr::null_mut();
            logs = false;
        }
        if self.rng.chance(0.5) {
            cb.allocateMemory = None;
            cb.freeMemory = None;
            cb.stepFinished = None;
        }
        let mut name_bytes: Vec<u8> = self.rng.pick(&SANE_NAMES).as_bytes().to_vec();
        if self.rng.chance(0.02) {
            name_bytes = "n".repeat(10_000).into_bytes();
        }
        let mut name_null = false;
        let mut guid = self.fmu.md.guid.clone();
        let mut guid_null = false;
        let mut fmu_type = if self.model.me && self.rng.chance(0.4) {
            MODEL_EXCHANGE
        } else {
            CO_SIMULATION
        };
        let mut callbacks_null = false;
        if hostile {
            expect_null = true;
            match self.rng.below(9) {
                0 => name_null = true,
                1 => name_bytes = vec![],
                2 => name_bytes = vec![b'a', 0xff, 0xfe],
                // Model Exchange is hostile only to an FMU that does not declare it.
                3 if !self.model.me => fmu_type = MODEL_EXCHANGE,
                3 => fmu_type = 2,
                4 => fmu_type = *self.rng.pick(&[2, 7, u32::MAX]),
                5 => guid_null = true,
                6 => {
                    guid = self
                        .rng
                        .pick(&["", "{00000000-0000-0000-0000-000000000000}", "garbage"])
                        .to_string()
                }
                7 => guid = guid.trim_matches(|c| c == '{' || c == '}').to_string(),
                _ => callbacks_null = true,
            }
        }
        let name = CString::new(name_bytes.clone()).expect("no NUL");
        let guid_c = CString::new(guid).expect("no NUL");
        let resources = match self.rng.below(3) {
            0 => None,
            1 => Some(CString::new("file:///tmp/mechfmu-robustness/resources/").unwrap()),
            _ => Some(CString::new("\u{1}garbage: not a URI %s").unwrap()),
        };
        let visible = *self.rng.pick(&[0, 1, 2, -1]);
        let logging_on = *self.rng.pick(&[0, 1, 1, 5, -1]);
        self.note(|| {
            format!(
                "fmi2Instantiate(name {:?}, type {fmu_type}, guid {}, callbacks {}, logger {}, loggingOn {logging_on})",
                if name_null { None } else { Some(String::from_utf8_lossy(&name_bytes).into_owned()) },
                if guid_null { "NULL".into() } else { format!("{:?}", guid_c) },
                if callbacks_null { "NULL" } else { "given" },
                logs
            )
        });
        // SAFETY: every pointer is NULL or valid for the call; the callbacks and the sink
        // outlive the instance (they move into `Inst`).
        let c = unsafe {
            (self.fmu.api.instantiate)(
                if name_null {
                    std::ptr::null()
                } else {
                    name.as_ptr()
                },
                fmu_type,
                if guid_null {
                    std::ptr::null()
                } else {
                    guid_c.as_ptr()
                },
                resources.as_ref().map_or(std::ptr::null(), |r| r.as_ptr()),
                if callbacks_null {
                    std::ptr::null()
                } else {
                    &*cb
                },
                visible,
                logging_on,
            )
        };
        self.stats.calls += 1;
        for v in sink.take_violations() {
            self.fail(format!("fmi2Instantiate: {v}"));
        }
        if expect_null {
            if !c.is_null() {
                self.fail(
                    "fmi2Instantiate accepted hostile arguments (returned an instance)".into(),
                );
                // SAFETY: the instance it returned.
                unsafe { (self.fmu.api.free_instance)(c) };
                return;
            }
            if logs && !callbacks_null && sink.is_empty() {
                self.fail("fmi2Instantiate refused its arguments without a logged message".into());
            }
            return;
        }
        if c.is_null() {
            let why = sink
                .all()
                .iter()
                .map(|m| m.text.clone())
                .collect::<Vec<_>>()
                .join("; ");
            self.fail(format!(
                "fmi2Instantiate failed with valid arguments: {why}"
            ));
            return;
        }
        let kind = if fmu_type == MODEL_EXCHANGE {
            self.stats.me_instances += 1;
            Kind::ModelExchange
        } else {
            Kind::CoSimulation
        };
        let mut inst = Inst::new(c, sink, name, logs, kind);
        inst._callbacks = Some(cb);
        inst.categories[0] = logging_on != 0;
        self.insts.push(inst);
    }

    /// A well-formed instance with a logger (for cleaning up).
    pub(crate) fn clean_instance(&mut self) {
        let sink = Box::<Sink>::default();
        let cb = Box::new(callbacks(&sink));
        let name = CString::new("cleanup").unwrap();
        let guid = CString::new(self.fmu.md.guid.as_str()).unwrap();
        // SAFETY: valid strings; callbacks and sink outlive the instance.
        let c = unsafe {
            (self.fmu.api.instantiate)(
                name.as_ptr(),
                CO_SIMULATION,
                guid.as_ptr(),
                std::ptr::null(),
                &*cb,
                0,
                0,
            )
        };
        self.stats.calls += 1;
        if c.is_null() {
            self.fail("fmi2Instantiate with valid arguments failed".into());
            return;
        }
        let mut inst = Inst::new(c, sink, name, true, Kind::CoSimulation);
        inst._callbacks = Some(cb);
        inst.categories[0] = false;
        self.insts.push(inst);
    }
}
