//! Text during constant evaluation, where nothing can allocate and `==` on `str` is not a
//! `const fn`: names compared ([`str_eq`]) and the messages of the declaration errors
//! `mechanism!` reports at compile time (the same text at run time).

/// A message of at most [`CAPACITY`](Self::CAPACITY) bytes, built piece by piece in a
/// `const fn`; longer text is cut at a character boundary.
#[derive(Clone, Copy)]
pub struct ConstMessage {
    bytes: [u8; Self::CAPACITY],
    len: usize,
}

impl ConstMessage {
    pub const CAPACITY: usize = 512;

    pub const fn new() -> Self {
        ConstMessage {
            bytes: [0; Self::CAPACITY],
            len: 0,
        }
    }

    /// Appends `text` (as much of it as fits, whole characters only).
    pub const fn push(&mut self, text: &str) -> &mut Self {
        let text = text.as_bytes();
        let mut end = text.len();
        if end > Self::CAPACITY - self.len {
            end = Self::CAPACITY - self.len;
            // back to the start of the character cut in two
            while end > 0 && end < text.len() && text[end] & 0xC0 == 0x80 {
                end -= 1;
            }
        }
        let mut i = 0;
        while i < end {
            self.bytes[self.len] = text[i];
            self.len += 1;
            i += 1;
        }
        self
    }

    /// Appends `text` between backticks.
    pub const fn quoted(&mut self, text: &str) -> &mut Self {
        self.push("`").push(text).push("`")
    }

    pub const fn as_str(&self) -> &str {
        match core::str::from_utf8(self.bytes.split_at(self.len).0) {
            Ok(text) => text,
            // `push` keeps whole characters of `&str`s
            Err(_) => "(a message that is not UTF-8)",
        }
    }
}

impl Default for ConstMessage {
    fn default() -> Self {
        Self::new()
    }
}

/// Whether `a` and `b` are the same text, in a `const fn`.
#[doc(hidden)]
pub const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::ConstMessage;

    #[test]
    fn pieces_join_and_long_text_is_cut_between_characters() {
        let mut m = ConstMessage::new();
        m.push("state ").quoted("x").push(" is fine");
        assert_eq!(m.as_str(), "state `x` is fine");

        let mut long = ConstMessage::new();
        long.push(&"a".repeat(ConstMessage::CAPACITY - 1))
            .push("θθ");
        assert_eq!(long.as_str().len(), ConstMessage::CAPACITY - 1);
        assert!(long.as_str().ends_with('a'));
    }

    const COMPOSED: ConstMessage = {
        let mut m = ConstMessage::new();
        m.push("at ").quoted("compile").push(" time");
        m
    };

    #[test]
    fn composes_in_a_constant() {
        assert_eq!(COMPOSED.as_str(), "at `compile` time");
    }
}
