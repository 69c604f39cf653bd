//! The worker's wire format: frames (u32 length + payload, little-endian) carrying the
//! JSON setup and its answer, then binary chunks of cases and their results.
//!
//! Everything read is checked against the bytes that are there before it is used, so a
//! malformed frame is an error message, never a panic or a huge allocation.

use mechfmu_host::log::Message;
use std::io::Read;

/// Reads one frame's payload into `payload` (its memory reused). `Ok(false)`: the stream
/// ended at a frame boundary.
pub fn read_frame(input: &mut impl Read, payload: &mut Vec<u8>) -> Result<bool, String> {
    let mut length = [0u8; 4];
    let mut got = 0;
    while got < length.len() {
        match input.read(&mut length[got..]) {
            Ok(0) if got == 0 => return Ok(false),
            Ok(0) => {
                return Err(format!(
                    "the input ended inside a frame's length ({got} of 4 bytes)"
                ))
            }
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(format!("cannot read the input: {e}")),
        }
    }
    let length = u32::from_le_bytes(length) as usize;
    payload.clear();
    // Read what arrives rather than allocate what a corrupt length claims.
    input
        .take(length as u64)
        .read_to_end(payload)
        .map_err(|e| format!("cannot read the input: {e}"))?;
    if payload.len() < length {
        return Err(format!(
            "the input ended inside a frame: {} of its {length} bytes",
            payload.len()
        ));
    }
    Ok(true)
}

/// `payload` framed, for the JSON answer to the setup.
pub fn frame(payload: &[u8]) -> Vec<u8> {
    let mut framed = Vec::with_capacity(4 + payload.len());
    framed.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    framed.extend_from_slice(payload);
    framed
}

/// Little-endian f64 values in place in a payload.
#[derive(Clone, Copy, Debug)]
pub struct F64s<'a>(&'a [u8]);

impl F64s<'_> {
    /// Value `i` (of as many as the payload's count said there are).
    pub fn get(&self, i: usize) -> f64 {
        let mut bytes = [0u8; 8];
        bytes.copy_from_slice(&self.0[8 * i..8 * i + 8]);
        f64::from_le_bytes(bytes)
    }
}

/// One case of a chunk request.
#[derive(Clone, Copy, Debug)]
pub struct Case<'a> {
    pub index: u64,
    /// One per start of the setup, in its order.
    pub starts: F64s<'a>,
    /// Rows of the input table (0: no input).
    pub rows: usize,
    /// `rows × (1 + inputs)` values, row-major: time, then each input.
    pub table: F64s<'a>,
}

/// A payload read front to back, each read checked against what remains.
struct Cursor<'a> {
    rest: &'a [u8],
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, what: &dyn Fn() -> String) -> Result<&'a [u8], String> {
        if n > self.rest.len() {
            return Err(format!(
                "{} needs {n} bytes, {} remain",
                what(),
                self.rest.len()
            ));
        }
        let (taken, rest) = self.rest.split_at(n);
        self.rest = rest;
        Ok(taken)
    }

    fn u32(&mut self, what: &dyn Fn() -> String) -> Result<u32, String> {
        let bytes = self.take(4, what)?;
        Ok(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
    }

    fn u64(&mut self, what: &dyn Fn() -> String) -> Result<u64, String> {
        let mut bytes = [0u8; 8];
        bytes.copy_from_slice(self.take(8, what)?);
        Ok(u64::from_le_bytes(bytes))
    }

    fn f64s(&mut self, count: usize, what: &dyn Fn() -> String) -> Result<F64s<'a>, String> {
        let n = count
            .checked_mul(8)
            .ok_or_else(|| format!("{}: {count} values overflow", what()))?;
        self.take(n, what).map(F64s)
    }
}

/// A chunk request as the Python side writes it, from each case's index, start values and
/// input rows (each row its time, then the inputs): what [`parse_chunk`] reads, for the
/// tests that feed a worker.
pub fn encode_chunk<S, T, R>(cases: &[(u64, S, T)]) -> Vec<u8>
where
    S: AsRef<[f64]>,
    T: AsRef<[R]>,
    R: AsRef<[f64]>,
{
    let mut bytes = (cases.len() as u32).to_le_bytes().to_vec();
    for (index, starts, rows) in cases {
        bytes.extend_from_slice(&index.to_le_bytes());
        for v in starts.as_ref() {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        let rows = rows.as_ref();
        bytes.extend_from_slice(&(rows.len() as u32).to_le_bytes());
        for v in rows.iter().flat_map(|row| row.as_ref()) {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    bytes
}

/// The cases of a chunk request, for a setup with `starts` start values and `inputs`
/// inputs; the whole chunk is checked before any case runs.
pub fn parse_chunk(payload: &[u8], starts: usize, inputs: usize) -> Result<Vec<Case<'_>>, String> {
    let mut cursor = Cursor { rest: payload };
    let n_cases = cursor.u32(&|| "the chunk's case count".into())? as usize;
    // Each case takes at least its index, its start values and its row count.
    let smallest_case = 12 + 8 * starts;
    let mut cases = Vec::with_capacity(n_cases.min(cursor.rest.len() / smallest_case + 1));
    for k in 0..n_cases {
        let what = |part: &str| format!("case {k} of {n_cases}: {part}");
        let index = cursor.u64(&|| what("its index"))?;
        let start_values = cursor.f64s(starts, &|| what("its start values"))?;
        let rows = cursor.u32(&|| what("its row count"))? as usize;
        let values = rows
            .checked_mul(1 + inputs)
            .ok_or_else(|| what("its input table is too large"))?;
        let table = cursor.f64s(values, &|| {
            what(&format!(
                "its input table ({rows} rows × {} columns)",
                1 + inputs
            ))
        })?;
        cases.push(Case {
            index,
            starts: start_values,
            rows,
            table,
        });
    }
    if !cursor.rest.is_empty() {
        return Err(format!(
            "{} bytes after the chunk's {n_cases} cases",
            cursor.rest.len()
        ));
    }
    Ok(cases)
}

/// What one case reports.
#[derive(Clone, Copy, Debug)]
pub struct CaseReport<'a> {
    pub index: u64,
    /// 0 when the case ran to the end, else the status of the FMI call that failed.
    pub status: u8,
    /// The FMI function that failed ("" when none did).
    pub function: &'a str,
    pub discard_time: f64,
    pub last_successful_time: f64,
    pub log: &'a [Message],
    pub summaries: &'a [f64],
    pub elapsed_s: f64,
    pub cpu_s: f64,
}

/// A chunk reply being written: the frame's length is filled in by [`Reply::finish`].
#[derive(Default)]
pub struct Reply {
    bytes: Vec<u8>,
}

impl Reply {
    /// Starts a reply of `n_cases` cases (the memory of the last one reused).
    pub fn start(&mut self, n_cases: u32) {
        self.bytes.clear();
        self.bytes.extend_from_slice(&[0; 4]);
        self.u32(n_cases);
    }

    pub fn case(&mut self, report: &CaseReport) {
        self.bytes.extend_from_slice(&report.index.to_le_bytes());
        self.bytes.push(report.status);
        self.string(report.function);
        self.f64(report.discard_time);
        self.f64(report.last_successful_time);
        self.u32(report.log.len() as u32);
        for message in report.log {
            self.bytes.push(message.status.min(u8::MAX.into()) as u8);
            self.string(&message.category);
            self.string(&message.text);
        }
        for &value in report.summaries {
            self.f64(value);
        }
        self.f64(report.elapsed_s);
        self.f64(report.cpu_s);
    }

    /// The framed reply.
    pub fn finish(&mut self) -> Result<&[u8], String> {
        let length = u32::try_from(self.bytes.len() - 4)
            .map_err(|_| format!("a reply of {} bytes does not fit a frame", self.bytes.len()))?;
        self.bytes[..4].copy_from_slice(&length.to_le_bytes());
        Ok(&self.bytes)
    }

    fn u32(&mut self, value: u32) {
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    fn f64(&mut self, value: f64) {
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    /// u32 length + UTF-8 (a log message is at most a few kB; longer ones are cut at a
    /// character boundary so the length fits).
    fn string(&mut self, text: &str) {
        let mut end = text.len().min(u32::MAX as usize);
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        self.u32(end as u32);
        self.bytes.extend_from_slice(&text.as_bytes()[..end]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A case of a request: index, start values, input rows.
    type Request = (u64, Vec<f64>, Vec<Vec<f64>>);

    fn chunk(cases: &[Request]) -> Vec<u8> {
        encode_chunk(cases)
    }

    #[test]
    fn frames_round_trip_and_end_at_a_boundary() {
        let mut stream = frame(b"{\"ok\": true}");
        stream.extend(frame(b""));
        let mut input = stream.as_slice();
        let mut payload = Vec::new();
        assert_eq!(read_frame(&mut input, &mut payload), Ok(true));
        assert_eq!(payload, b"{\"ok\": true}");
        assert_eq!(read_frame(&mut input, &mut payload), Ok(true));
        assert!(payload.is_empty());
        assert_eq!(read_frame(&mut input, &mut payload), Ok(false));
    }

    #[test]
    fn a_short_frame_is_an_error() {
        let mut payload = Vec::new();
        let message = read_frame(&mut &[5u8, 0][..], &mut payload).unwrap_err();
        assert!(message.contains("inside a frame's length"), "{message}");
        // A length of 4 GiB with 3 bytes behind it: no allocation of 4 GiB, an error.
        let message =
            read_frame(&mut &[255u8, 255, 255, 255, 1, 2, 3][..], &mut payload).unwrap_err();
        assert!(message.contains("3 of its 4294967295 bytes"), "{message}");
    }

    #[test]
    fn chunks_parse_into_cases() {
        let bytes = chunk(&[
            (7, vec![1.5, 2.0], vec![]),
            (
                9,
                vec![-1.0, f64::NAN],
                vec![vec![0.0, 1.0], vec![2.0, 3.0]],
            ),
        ]);
        let cases = parse_chunk(&bytes, 2, 1).unwrap();
        assert_eq!(cases.len(), 2);
        assert_eq!(
            (cases[0].index, cases[0].rows, cases[0].table.0.len()),
            (7, 0, 0)
        );
        assert_eq!(cases[0].starts.get(0), 1.5);
        assert_eq!((cases[1].index, cases[1].rows), (9, 2));
        assert!(cases[1].starts.get(1).is_nan());
        assert_eq!(cases[1].table.get(3), 3.0);
    }

    #[test]
    fn malformed_chunks_are_errors() {
        let good = chunk(&[(1, vec![1.0], vec![vec![0.0, 1.0]])]);
        // Cut anywhere: an error naming what is missing.
        for cut in 0..good.len() {
            assert!(parse_chunk(&good[..cut], 1, 1).is_err(), "cut at {cut}");
        }
        // Bytes left over.
        let mut long = good.clone();
        long.push(0);
        let message = parse_chunk(&long, 1, 1).unwrap_err();
        assert!(message.contains("1 bytes after"), "{message}");
        // A case count far beyond the bytes: refused, nothing of that size allocated.
        let mut many = good.clone();
        many[..4].copy_from_slice(&u32::MAX.to_le_bytes());
        let message = parse_chunk(&many, 1, 1).unwrap_err();
        assert!(
            message.contains("case 1 of 4294967295: its index"),
            "{message}"
        );
        // A row count far beyond the bytes.
        let mut rows = good.clone();
        rows[20..24].copy_from_slice(&u32::MAX.to_le_bytes());
        let message = parse_chunk(&rows, 1, 1).unwrap_err();
        assert!(message.contains("4294967295 rows × 2 columns"), "{message}");
        // The wrong number of start values for the setup.
        assert!(parse_chunk(&good, 2, 1).is_err());
    }

    /// A case of a reply: index, status, function, log, summaries.
    type Answer = (u64, u8, String, Vec<Message>, Vec<f64>);

    /// Reads back what [`Reply`] wrote (the Python side's decoder, in Rust).
    fn decode(reply: &[u8], summaries: usize) -> Vec<Answer> {
        let mut cursor = Cursor { rest: reply };
        let what = || String::from("test");
        assert_eq!(cursor.u32(&what).unwrap() as usize, reply.len() - 4);
        let n = cursor.u32(&what).unwrap();
        let string = |c: &mut Cursor| {
            let n = c.u32(&what).unwrap() as usize;
            String::from_utf8(c.take(n, &what).unwrap().to_vec()).unwrap()
        };
        let mut cases = Vec::new();
        for _ in 0..n {
            let index = cursor.u64(&what).unwrap();
            let status = cursor.take(1, &what).unwrap()[0];
            let function = string(&mut cursor);
            cursor.f64s(2, &what).unwrap();
            let log = (0..cursor.u32(&what).unwrap())
                .map(|_| Message {
                    status: cursor.take(1, &what).unwrap()[0].into(),
                    category: string(&mut cursor),
                    text: string(&mut cursor),
                })
                .collect();
            let values = cursor.f64s(summaries + 2, &what).unwrap();
            let values = (0..summaries).map(|i| values.get(i)).collect();
            cases.push((index, status, function, log, values));
        }
        assert!(cursor.rest.is_empty());
        cases
    }

    #[test]
    fn replies_round_trip() {
        let log = [Message {
            status: 3,
            category: "logStatusError".into(),
            text: "m = -1 is not positive: ✗".into(),
        }];
        let report = |index, status, function, log, summaries| CaseReport {
            index,
            status,
            function,
            discard_time: f64::NAN,
            last_successful_time: f64::NAN,
            log,
            summaries,
            elapsed_s: 1e-3,
            cpu_s: 9e-4,
        };
        let mut reply = Reply::default();
        reply.start(2);
        reply.case(&report(4, 0, "", &[], &[1.25, -2.0]));
        reply.case(&report(5, 3, "fmi2SetReal", &log, &[f64::NAN; 2]));
        let cases = decode(reply.finish().unwrap(), 2);
        assert_eq!(cases[0].0, 4);
        assert_eq!(cases[0].4, [1.25, -2.0]);
        assert_eq!((cases[1].1, cases[1].2.as_str()), (3, "fmi2SetReal"));
        assert_eq!(cases[1].3, log);
        // The memory is reused and the frame rewritten.
        reply.start(0);
        assert_eq!(reply.finish().unwrap(), [4, 0, 0, 0, 0, 0, 0, 0]);
    }
}
