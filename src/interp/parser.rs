//! The script parser: Tcl's twelve rules (the "Dodekalogue") turned into the
//! internal form `Script` -> `Command` -> `Word` -> `Part` (molt's shape).
//!
//! The grammar is context-sensitive (braces nest, `#` is a comment only where
//! a command starts, `]` ends a nested script only at its own level), so this
//! is a hand-written byte scanner; logos handles the regular `expr` tokens.
//! Parsing never panics; a syntax error is data (`ParseError`) carrying the
//! line where the unclosed construct opened. A `Script` keeps the commands
//! before its first syntax error, which still run (as in Tcl 8.6).

use std::rc::Rc;

use super::value::Value;

/// Nested `[...]` deeper than this is refused rather than overflowing.
const MAX_PARSE_DEPTH: usize = 1000;

pub struct Script {
    pub(crate) cmds: Vec<Command>,
    pub(crate) error: Option<ParseError>,
    pub(crate) src: Rc<str>,
    pub(crate) file: Option<Rc<str>>,
    /// The absolute line of the script's first character.
    pub(crate) first_line: u32,
    /// Lines its text lost to backslash-newlines its braces replaced by a
    /// space (only `info frame` counts them, as Tcl does).
    pub(crate) cont: Option<Rc<Cont>>,
}

/// The lines a braced word lost to backslash-newlines (each became a
/// space): `base` were lost before the word's text starts (in the text
/// around it), and one at each position in `at` within it.
#[derive(Debug, Default)]
pub(crate) struct Cont {
    pub(crate) base: u32,
    pub(crate) at: Box<[u32]>,
}

impl Cont {
    /// Lines lost before byte `pos` of the text.
    pub(crate) fn before(&self, pos: u32) -> u32 {
        self.base + self.at.partition_point(|&p| p < pos) as u32
    }
}

pub struct Command {
    pub(crate) words: Vec<Word>,
    /// Absolute line of the command's first word.
    pub(crate) line: u32,
    pub(crate) start: u32,
    pub(crate) end: u32,
}

pub enum Word {
    /// Fully known at parse time.
    Lit(Value),
    Var(VarName),
    Cmd(Rc<Script>),
    Concat(Vec<Part>),
    /// `{*}word`.
    Expand(Box<Word>),
    /// In a compiled body (`compile.rs`): `$name` of a local, by slot.
    Local(u32, Rc<str>),
    /// In a compiled body: `$name(index)` of a local array, by slot.
    LocalElem(u32, Rc<str>, Box<Word>),
    /// In a compiled body: a compiled `[...]`.
    Compiled(Rc<super::compile::Body>),
}

pub enum Part {
    Lit(String),
    Var(VarName),
    Cmd(Rc<Script>),
    /// As `Word::Local` and `Word::Compiled`.
    Local(u32, Rc<str>),
    Compiled(Rc<super::compile::Body>),
}

pub enum VarName {
    Scalar(Rc<str>),
    Elem(Rc<str>, Box<Word>),
}

#[derive(Clone, Debug)]
pub struct ParseError {
    pub msg: String,
    /// Absolute line where the unclosed construct opened (or the error is).
    pub line: u32,
    /// True when more input could complete the script (`info complete`).
    pub incomplete: bool,
    /// Byte offset of the command that failed to parse.
    pub(crate) cmd_start: u32,
    pub(crate) pos: u32,
}

impl Script {
    /// Parses a whole script. Commands up to the first syntax error are kept.
    #[cfg(test)]
    pub fn parse(src: Rc<str>, file: Option<Rc<str>>, first_line: u32) -> Script {
        Script::parse_with(src, file, first_line, None)
    }

    /// `parse` of a braced word's text, with the lines it lost.
    pub(crate) fn parse_with(
        src: Rc<str>,
        file: Option<Rc<str>>,
        first_line: u32,
        cont: Option<Rc<Cont>>,
    ) -> Script {
        let mut p = Parser::new(src.clone(), file.clone(), first_line).with_cont(cont.clone());
        let mut cmds = Vec::new();
        let mut error = None;
        while let Some(r) = p.next_command() {
            match r {
                Ok(c) => cmds.push(c),
                Err(e) => {
                    error = Some(e);
                    break;
                }
            }
        }
        Script { cmds, error, src, file, first_line, cont }
    }

    /// The line of a command as `info frame` counts it: with the lines
    /// backslash-newlines in braces took out.
    pub(crate) fn true_line(&self, cmd: &Command) -> u32 {
        cmd.line + self.cont.as_ref().map_or(0, |c| c.before(cmd.start))
    }

    /// The first line as `info frame` counts it.
    pub(crate) fn true_first_line(&self) -> u32 {
        self.first_line + self.cont.as_ref().map_or(0, |c| c.base)
    }

    /// A command's text as errorInfo shows it: with the blanks before its
    /// terminator, as Tcl's parser counts them in.
    pub(crate) fn text(&self, cmd: &Command) -> &str {
        let end = cmd.end as usize;
        let blanks = self.src.as_bytes()[end..].iter().take_while(|&&c| c == b' ' || c == b'\t');
        &self.src[cmd.start as usize..end + blanks.count()]
    }
}

/// True when the script has no unclosed brace, bracket or quote.
pub fn is_complete(src: &str) -> bool {
    let mut p = Parser::new(Rc::from(src), None, 1);
    while let Some(r) = p.next_command() {
        if let Err(e) = r {
            return !e.incomplete;
        }
    }
    true
}

/// A lookup table: true for the given bytes.
const fn byte_table(bytes: &[u8]) -> [bool; 256] {
    let mut t = [false; 256];
    let mut i = 0;
    while i < bytes.len() {
        t[bytes[i] as usize] = true;
        i += 1;
    }
    t
}

/// Byte classes for the fast scan of plain words.
const SPECIAL: [bool; 256] = byte_table(b" \t\n\r\x0b\x0c;\\$[]");

/// Bytes that end a word at the top level: blanks, newline, `;`.
const WORD_END: [bool; 256] = byte_table(b" \t\n\r\x0b\x0c;");

/// Blanks between words (not newline).
const BLANK: [bool; 256] = byte_table(b" \t\r\x0b\x0c");

fn is_blank(c: u8) -> bool {
    BLANK[c as usize]
}

fn hex_val(c: u8) -> Option<u32> {
    (c as char).to_digit(16)
}

/// One backslash sequence starting at `s[i] == '\\'`: the character it
/// stands for and how many bytes it used.
pub(crate) fn backslash(s: &str, i: usize) -> (char, usize) {
    let b = s.as_bytes();
    if i + 1 >= b.len() {
        return ('\\', 1);
    }
    let c = b[i + 1];
    let hex = |max: usize| {
        let mut v = 0u32;
        let mut n = 0;
        while n < max && i + 2 + n < b.len() {
            match hex_val(b[i + 2 + n]) {
                Some(d) => v = v * 16 + d,
                None => break,
            }
            n += 1;
        }
        (v, n)
    };
    match c {
        b'a' => ('\x07', 2),
        b'b' => ('\x08', 2),
        b'f' => ('\x0c', 2),
        b'n' => ('\n', 2),
        b'r' => ('\r', 2),
        b't' => ('\t', 2),
        b'v' => ('\x0b', 2),
        b'\n' => {
            let mut j = i + 2;
            while j < b.len() && is_blank(b[j]) {
                j += 1;
            }
            (' ', j - i)
        }
        b'x' | b'u' | b'U' => {
            let max = match c {
                b'x' => 2,
                b'u' => 4,
                _ => 8,
            };
            let (v, n) = hex(max);
            if n == 0 { (c as char, 2) } else { (char::from_u32(v).unwrap_or('\u{fffd}'), 2 + n) }
        }
        b'0'..=b'7' => {
            let mut v = 0u32;
            let mut n = 0;
            while n < 3 && i + 1 + n < b.len() && (b'0'..=b'7').contains(&b[i + 1 + n]) {
                v = v * 8 + (b[i + 1 + n] - b'0') as u32;
                n += 1;
            }
            (char::from_u32(v & 0xff).unwrap_or('\u{fffd}'), 1 + n)
        }
        _ => {
            let ch = s[i + 1..].chars().next().unwrap_or('\\');
            (ch, 1 + ch.len_utf8())
        }
    }
}

/// Collects the pieces of a word with substitutions.
#[derive(Default)]
struct Parts {
    parts: Vec<Part>,
    lit: String,
}

impl Parts {
    fn push_var(&mut self, v: VarName) {
        self.flush();
        self.parts.push(Part::Var(v));
    }
    fn push_cmd(&mut self, s: Rc<Script>) {
        self.flush();
        self.parts.push(Part::Cmd(s));
    }
    fn flush(&mut self) {
        if !self.lit.is_empty() {
            self.parts.push(Part::Lit(std::mem::take(&mut self.lit)));
        }
    }
    fn into_word(mut self) -> Word {
        self.flush();
        if self.parts.len() == 1 {
            match self.parts.pop() {
                Some(Part::Lit(s)) => return Word::Lit(Value::from_string(s)),
                Some(Part::Var(v)) => return Word::Var(v),
                Some(Part::Cmd(c)) => return Word::Cmd(c),
                Some(p @ (Part::Local(..) | Part::Compiled(_))) => self.parts.push(p),
                None => {}
            }
        }
        if self.parts.is_empty() {
            return Word::Lit(Value::empty());
        }
        Word::Concat(self.parts)
    }
}

/// A plain word of a fast-path command: its span in the source.
#[derive(Clone, Copy)]
pub(crate) struct PlainWord {
    pub(crate) start: u32,
    pub(crate) end: u32,
}

pub(crate) enum Plain {
    Cmd { line: u32, start: u32, end: u32 },
    Complex,
    End,
}

/// Skips white space, command separators and comments from `pos`.
fn skip_separators(b: &[u8], mut pos: usize) -> usize {
    let len = b.len();
    loop {
        while pos < len {
            let c = b[pos];
            if is_blank(c) || c == b'\n' || c == b';' {
                pos += 1;
            } else if c == b'\\' && pos + 1 < len && b[pos + 1] == b'\n' {
                pos += 2;
            } else {
                break;
            }
        }
        if pos < len && b[pos] == b'#' {
            while pos < len && b[pos] != b'\n' {
                if b[pos] == b'\\' {
                    pos += 1;
                }
                pos += 1;
            }
            pos = pos.min(len);
            continue;
        }
        return pos;
    }
}

/// The scanner for plain commands, over bytes only: it makes no values, so
/// it can run on another thread ahead of evaluation.
pub(crate) struct PlainScanner<'a> {
    pub(crate) b: &'a [u8],
    pub(crate) pos: usize,
    ck_pos: usize,
    ck_line: u32,
}

impl<'a> PlainScanner<'a> {
    pub(crate) fn new(b: &'a [u8], first_line: u32) -> PlainScanner<'a> {
        PlainScanner { b, pos: 0, ck_pos: 0, ck_line: first_line }
    }

    pub(crate) fn line_at(&mut self, pos: usize) -> u32 {
        if pos >= self.ck_pos {
            self.ck_line += self.b[self.ck_pos..pos].iter().filter(|&&c| c == b'\n').count() as u32;
        } else {
            self.ck_line -= self.b[pos..self.ck_pos].iter().filter(|&&c| c == b'\n').count() as u32;
        }
        self.ck_pos = pos;
        self.ck_line
    }

    /// The next command if every word in it is plain (no quoting or
    /// substitution), as byte spans, reading simple decimal numbers on the
    /// way; `NotPlain` leaves the position at the command so a full parser
    /// can take over.
    pub(crate) fn next(&mut self, spans: &mut smallvec::SmallVec<[PlainWord; 8]>) -> Plain {
        spans.clear();
        self.pos = skip_separators(self.b, self.pos);
        let b = self.b;
        let len = b.len();
        if self.pos >= len {
            return Plain::End;
        }
        let start = self.pos;
        let mut p = start;
        loop {
            while p < len && is_blank(b[p]) {
                p += 1;
            }
            if p >= len || b[p] == b'\n' || b[p] == b';' {
                break;
            }
            let ws = p;
            if b[p] == b'{' || b[p] == b'"' {
                return Plain::Complex;
            }
            while p < len && !SPECIAL[b[p] as usize] {
                p += 1;
            }
            if p < len && !WORD_END[b[p] as usize] {
                return Plain::Complex;
            }
            spans.push(PlainWord { start: ws as u32, end: p as u32 });
        }
        let mut end = p;
        while end > start && is_blank(b[end - 1]) {
            end -= 1;
        }
        let ends_line = p < len && b[p] == b'\n';
        self.pos = if p < len { p + 1 } else { p };
        let line = self.line_at(start);
        if ends_line {
            // The command holds no newline but its terminator: move the line
            // checkpoint past it so the next command counts nothing again.
            self.ck_pos = self.pos;
            self.ck_line = line + 1;
        }
        Plain::Cmd { line, start: start as u32, end: end as u32 }
    }
}

pub struct Parser {
    src: Rc<str>,
    pos: usize,
    file: Option<Rc<str>>,
    ck_pos: usize,
    ck_line: u32,
    depth: usize,
    /// The lines the text lost, if it is a braced word's (see `Cont`).
    cont: Option<Rc<Cont>>,
}

impl Parser {
    pub fn new(src: Rc<str>, file: Option<Rc<str>>, first_line: u32) -> Parser {
        Parser { src, pos: 0, file, ck_pos: 0, ck_line: first_line, depth: 0, cont: None }
    }

    /// The lines the text lost (see `Cont`), when it is a braced word's.
    pub(crate) fn with_cont(mut self, cont: Option<Rc<Cont>>) -> Parser {
        self.cont = cont;
        self
    }

    pub fn src(&self) -> &Rc<str> {
        &self.src
    }

    fn line_at(&mut self, pos: usize) -> u32 {
        let b = self.src.as_bytes();
        if pos >= self.ck_pos {
            self.ck_line += b[self.ck_pos..pos].iter().filter(|&&c| c == b'\n').count() as u32;
        } else {
            self.ck_line -= b[pos..self.ck_pos].iter().filter(|&&c| c == b'\n').count() as u32;
        }
        self.ck_pos = pos;
        self.ck_line
    }

    /// The lines a braced word at `open`..`close` lost: those this text
    /// lost before it and inside it, and those its own braces took out.
    fn word_cont(&self, open: usize, close: usize, lost: Vec<u32>) -> Option<Rc<Cont>> {
        let start = open as u32 + 1;
        let (base, mut at) = match &self.cont {
            Some(c) => {
                let inside = c.at.iter().filter(|&&p| p >= start && p < close as u32);
                (c.before(start), inside.map(|p| p - start).collect::<Vec<u32>>())
            }
            None => (0, Vec::new()),
        };
        if base == 0 && at.is_empty() && lost.is_empty() {
            return None;
        }
        // A text that lost lines has no backslash-newline left, so at most
        // one of the two lists has anything.
        at.extend(lost);
        Some(Rc::new(Cont { base, at: at.into() }))
    }

    fn err(&mut self, msg: &str, at: usize, incomplete: bool, cmd_start: usize) -> ParseError {
        ParseError {
            msg: msg.to_string(),
            line: self.line_at(at),
            incomplete,
            cmd_start: cmd_start as u32,
            pos: self.pos as u32,
        }
    }

    fn is_word_end(&self, c: u8, nested: bool) -> bool {
        is_blank(c) || c == b'\n' || c == b';' || (nested && c == b']')
    }

    /// Whether a word may end before `pos`: a separator, or a
    /// backslash-newline (which Tcl reads as a space).
    fn word_ends_at(&self, pos: usize, nested: bool) -> bool {
        let b = self.src.as_bytes();
        self.is_word_end(b[pos], nested) || (b[pos] == b'\\' && b.get(pos + 1) == Some(&b'\n'))
    }

    pub(crate) fn pos(&self) -> usize {
        self.pos
    }

    pub(crate) fn set_pos(&mut self, pos: usize) {
        self.pos = pos;
    }

    /// An `expr` operand that starts with `$`, `[`, `"` or `{`.
    /// The whole source as `subst` reads it: text with the substitutions
    /// asked for (backslashes, `[commands]`, `$variables`) and the others
    /// left as written.
    pub(crate) fn subst_parts(
        &mut self,
        backslashes: bool,
        commands: bool,
        variables: bool,
    ) -> Result<Vec<Part>, ParseError> {
        let mut parts = Parts::default();
        while self.pos < self.src.len() {
            let c = self.src.as_bytes()[self.pos];
            let literal = match c {
                b'\\' => !backslashes,
                b'[' => !commands,
                b'$' => !variables,
                _ => false,
            };
            if literal {
                parts.lit.push(c as char);
                self.pos += 1;
            } else {
                // `"` is no delimiter here: it only ends a run of text.
                self.part(&mut parts, false, 0, b'"')?;
            }
        }
        parts.flush();
        Ok(parts.parts)
    }

    pub(crate) fn expr_word(&mut self) -> Result<Word, ParseError> {
        match self.src.as_bytes()[self.pos] {
            b'$' => match self.var(false, 0)? {
                Some(v) => Ok(Word::Var(v)),
                None => Err(self.err("invalid character \"$\"", self.pos, false, 0)),
            },
            b'[' => Ok(Word::Cmd(self.cmd_subst(0)?)),
            b'"' => self.quoted(false, 0, false),
            _ => self.braced(false, 0, false),
        }
    }

    /// The next top-level command, or `None` at the end of the script.
    pub fn next_command(&mut self) -> Option<Result<Command, ParseError>> {
        self.command(false)
    }

    /// Skips separators and comments; false at the end of the (nested) script.
    fn skip_to_command(&mut self, nested: bool) -> bool {
        self.pos = skip_separators(self.src.as_bytes(), self.pos);
        !(self.pos >= self.src.len() || (nested && self.src.as_bytes()[self.pos] == b']'))
    }

    /// See `PlainScanner::next`.
    pub(crate) fn next_plain(&mut self, spans: &mut smallvec::SmallVec<[PlainWord; 8]>) -> Plain {
        let src = self.src.clone();
        let mut sc = PlainScanner {
            b: src.as_bytes(),
            pos: self.pos,
            ck_pos: self.ck_pos,
            ck_line: self.ck_line,
        };
        let r = sc.next(spans);
        self.pos = sc.pos;
        self.ck_pos = sc.ck_pos;
        self.ck_line = sc.ck_line;
        r
    }

    fn command(&mut self, nested: bool) -> Option<Result<Command, ParseError>> {
        let len = self.src.len();
        if !self.skip_to_command(nested) {
            return None;
        }
        let start = self.pos;
        let line = self.line_at(start);
        let mut words = Vec::with_capacity(4);
        let mut end;
        loop {
            let b = self.src.as_bytes();
            while self.pos < len {
                let c = b[self.pos];
                if is_blank(c) {
                    self.pos += 1;
                } else if c == b'\\' && self.pos + 1 < len && b[self.pos + 1] == b'\n' {
                    self.pos += 2;
                } else {
                    break;
                }
            }
            end = self.pos;
            if self.pos >= len {
                break;
            }
            let c = b[self.pos];
            if c == b'\n' || c == b';' {
                self.pos += 1;
                break;
            }
            if nested && c == b']' {
                break;
            }
            match self.word(nested, start) {
                Ok(w) => words.push(w),
                Err(e) => return Some(Err(e)),
            }
        }
        while end > start && is_blank(self.src.as_bytes()[end - 1]) {
            end -= 1;
        }
        Some(Ok(Command { words, line, start: start as u32, end: end as u32 }))
    }

    fn word(&mut self, nested: bool, cmd_start: usize) -> Result<Word, ParseError> {
        let b = self.src.as_bytes();
        let len = b.len();
        let p = self.pos;
        if b[p..].starts_with(b"{*}") && p + 3 < len && !self.is_word_end(b[p + 3], nested) {
            self.pos += 3;
            let w = self.word(nested, cmd_start)?;
            return Ok(Word::Expand(Box::new(w)));
        }
        match b[p] {
            b'{' => self.braced(nested, cmd_start, true),
            b'"' => self.quoted(nested, cmd_start, true),
            _ => self.bare(nested, cmd_start),
        }
    }

    fn braced(
        &mut self,
        nested: bool,
        cmd_start: usize,
        check_end: bool,
    ) -> Result<Word, ParseError> {
        let open = self.pos;
        let len = self.src.len();
        let mut depth = 1;
        let mut out: Option<String> = None;
        // Where in the content a backslash-newline became a space.
        let mut lost: Vec<u32> = Vec::new();
        let mut pos = open + 1;
        let mut run = pos;
        {
            let b = self.src.as_bytes();
            loop {
                if pos >= len {
                    self.pos = len;
                    return Err(self.err("missing close-brace", open, true, cmd_start));
                }
                match b[pos] {
                    b'\\' => {
                        if pos + 1 < len && b[pos + 1] == b'\n' {
                            let o = out.get_or_insert_with(String::new);
                            o.push_str(&self.src[run..pos]);
                            lost.push(o.len() as u32);
                            o.push(' ');
                            pos += 2;
                            while pos < len && is_blank(b[pos]) {
                                pos += 1;
                            }
                            run = pos;
                        } else {
                            pos += 2;
                        }
                    }
                    b'{' => {
                        depth += 1;
                        pos += 1;
                    }
                    b'}' => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                        pos += 1;
                    }
                    _ => pos += 1,
                }
            }
        }
        let content = match out {
            Some(mut o) => {
                o.push_str(&self.src[run..pos]);
                o
            }
            None => self.src[open + 1..pos].to_string(),
        };
        self.pos = pos + 1;
        if check_end && self.pos < len && !self.word_ends_at(self.pos, nested) {
            return Err(self.err("extra characters after close-brace", self.pos, false, cmd_start));
        }
        let line = self.line_at(open);
        let cont = self.word_cont(open, pos, lost);
        Ok(Word::Lit(Value::with_origin(content, self.file.clone(), line, cont)))
    }

    fn quoted(
        &mut self,
        nested: bool,
        cmd_start: usize,
        check_end: bool,
    ) -> Result<Word, ParseError> {
        let open = self.pos;
        self.pos += 1;
        let mut parts = Parts::default();
        loop {
            if self.pos >= self.src.len() {
                return Err(self.err("missing \"", open, true, cmd_start));
            }
            if self.src.as_bytes()[self.pos] == b'"' {
                break;
            }
            self.part(&mut parts, nested, cmd_start, b'"')?;
        }
        self.pos += 1;
        if check_end && self.pos < self.src.len() && !self.word_ends_at(self.pos, nested) {
            return Err(self.err("extra characters after close-quote", self.pos, false, cmd_start));
        }
        Ok(parts.into_word())
    }

    fn bare(&mut self, nested: bool, cmd_start: usize) -> Result<Word, ParseError> {
        let start = self.pos;
        let b = self.src.as_bytes();
        let len = b.len();
        // Fast path: a word of plain characters.
        let mut p = start;
        while p < len && !SPECIAL[b[p] as usize] {
            p += 1;
        }
        if p >= len || self.is_word_end(b[p], nested) {
            self.pos = p;
            return Ok(Word::Lit(Value::from(&self.src[start..p])));
        }
        let mut parts = Parts::default();
        loop {
            let b = self.src.as_bytes();
            if self.pos >= len || self.is_word_end(b[self.pos], nested) {
                break;
            }
            if b[self.pos] == b'\\' && self.pos + 1 < len && b[self.pos + 1] == b'\n' {
                break;
            }
            self.part(&mut parts, nested, cmd_start, 0)?;
        }
        Ok(parts.into_word())
    }

    /// One piece of a quoted or bare word (or an array index): a run of
    /// plain text, a backslash sequence, a variable or a command.
    fn part(
        &mut self,
        parts: &mut Parts,
        nested: bool,
        cmd_start: usize,
        close: u8,
    ) -> Result<(), ParseError> {
        let b = self.src.as_bytes();
        let len = b.len();
        match b[self.pos] {
            b'\\' => {
                let (c, n) = backslash(&self.src, self.pos);
                parts.lit.push(c);
                self.pos += n;
            }
            b'$' => match self.var(nested, cmd_start)? {
                Some(v) => parts.push_var(v),
                None => parts.lit.push('$'),
            },
            b'[' => {
                let s = self.cmd_subst(cmd_start)?;
                parts.push_cmd(s);
            }
            _ => {
                let start = self.pos;
                let mut p = self.pos + 1;
                while p < len {
                    let c = b[p];
                    if c == b'\\' || c == b'$' || c == b'[' || c == close {
                        break;
                    }
                    if close == 0 && self.is_word_end(c, nested) {
                        break;
                    }
                    p += 1;
                }
                parts.lit.push_str(&self.src[start..p]);
                self.pos = p;
            }
        }
        Ok(())
    }

    fn cmd_subst(&mut self, cmd_start: usize) -> Result<Rc<Script>, ParseError> {
        let open = self.pos;
        if self.depth >= MAX_PARSE_DEPTH {
            return Err(self.err("too many nested brackets", open, false, cmd_start));
        }
        self.pos += 1;
        self.depth += 1;
        let first_line = self.line_at(self.pos);
        let mut cmds = Vec::new();
        while let Some(r) = self.command(true) {
            match r {
                Ok(c) => cmds.push(c),
                Err(e) => {
                    self.depth -= 1;
                    return Err(e);
                }
            }
        }
        self.depth -= 1;
        if self.pos >= self.src.len() {
            return Err(self.err("missing close-bracket", open, true, cmd_start));
        }
        self.pos += 1; // the ']'
        Ok(Rc::new(Script {
            cmds,
            error: None,
            src: self.src.clone(),
            file: self.file.clone(),
            first_line,
            cont: self.cont.clone(),
        }))
    }

    /// A variable reference at `$`; `None` when the `$` is literal.
    fn var(&mut self, nested: bool, cmd_start: usize) -> Result<Option<VarName>, ParseError> {
        let b = self.src.as_bytes();
        let len = b.len();
        let dollar = self.pos;
        let mut p = dollar + 1;
        if p < len && b[p] == b'{' {
            let close = self.src[p + 1..].find('}');
            return match close {
                None => {
                    self.pos = len;
                    Err(self.err("missing close-brace for variable name", dollar, true, cmd_start))
                }
                Some(n) => {
                    let name: Rc<str> = Rc::from(&self.src[p + 1..p + 1 + n]);
                    self.pos = p + 2 + n;
                    Ok(Some(VarName::Scalar(name)))
                }
            };
        }
        loop {
            if p < len && (b[p].is_ascii_alphanumeric() || b[p] == b'_') {
                p += 1;
            } else if p + 1 < len && b[p] == b':' && b[p + 1] == b':' {
                p += 2;
                while p < len && b[p] == b':' {
                    p += 1;
                }
            } else {
                break;
            }
        }
        if p == dollar + 1 {
            self.pos = dollar + 1;
            return Ok(None);
        }
        let name: Rc<str> = Rc::from(&self.src[dollar + 1..p]);
        self.pos = p;
        if p < len && b[p] == b'(' {
            self.pos = p + 1;
            let mut parts = Parts::default();
            loop {
                if self.pos >= len {
                    return Err(self.err("missing )", p, true, cmd_start));
                }
                if self.src.as_bytes()[self.pos] == b')' {
                    break;
                }
                self.index_part(&mut parts, nested, cmd_start)?;
            }
            self.pos += 1;
            return Ok(Some(VarName::Elem(name, Box::new(parts.into_word()))));
        }
        Ok(Some(VarName::Scalar(name)))
    }

    fn index_part(
        &mut self,
        parts: &mut Parts,
        nested: bool,
        cmd_start: usize,
    ) -> Result<(), ParseError> {
        let b = self.src.as_bytes();
        match b[self.pos] {
            b'\\' | b'$' | b'[' => self.part(parts, nested, cmd_start, b')'),
            _ => {
                let start = self.pos;
                let mut p = self.pos;
                while p < b.len() && !matches!(b[p], b'\\' | b'$' | b'[' | b')') {
                    p += 1;
                }
                parts.lit.push_str(&self.src[start..p]);
                self.pos = p;
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests;
