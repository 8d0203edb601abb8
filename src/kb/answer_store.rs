//! Answers kept between runs. With the built-in rules alone (no `--kb`
//! file, no query typed), an answer depends only on the rules' text, the
//! bounds changed so far in the run, and the question's text: the same
//! three give the same answer in every run. The store keeps them in a
//! file, each under a key made of the three, so a later run asks the engine
//! only what no run asked before, and builds no engine at all when every
//! question was asked before (the engine's build is most of a small
//! domain's time). The mesh and the trace are the same with or without
//! it; a store that cannot be read is an empty one, one that cannot be
//! written is left as it was.
//!
//! Where: `$FREEMESH_ANSWER_STORE` (a folder; `off` for none), else the
//! user's cache folder (`~/.cache/freemesh` on Linux).

use std::collections::HashMap;
use std::io::Write;
use std::path::PathBuf;
use std::sync::{Mutex, OnceLock};

use scryer_prolog::Term;

use crate::kb::terms::Bindings;

/// The file format; a change of it, of the crate's version or of any
/// rule's text names another file.
const FORMAT: &str = "freemesh answer store 3";

/// The engine whose answers are kept (another version may answer
/// otherwise; a test holds it to `Cargo.lock`'s).
const ENGINE: &str = "scryer-prolog 0.10.0";

/// The most answers a store keeps (about 8 MB: read in a few
/// milliseconds, and not parsed: the file is its own index); past it, a
/// run's new answers and the kept ones it used stay, and take the place
/// of those the longest unused (each answer carries the number of the
/// last run that wrote it or used it): the domains meshed last find
/// their answers whatever was meshed before them. (Dropped by key, as
/// before, one run's new answers made every other domain's run build
/// its engine again once the store was full.)
const MOST_ANSWERS: usize = 100_000;

/// The key of one question: the rules' state and the question's text.
pub type Key = u128;

struct Store {
    path: PathBuf,
    /// The answers read from the file.
    read: StoreFile,
    /// Answers this run found, encoded.
    new: HashMap<Key, Vec<u8>>,
    /// Which of the answers read this run used.
    used: Vec<bool>,
}

/// A store file as read: the format's line, the count `n`, the next
/// run's number, the `n` keys in increasing order, the number of the run
/// that last wrote or used each, `n + 1` offsets into the encoded
/// answers, and the answers; a key is found by a binary search, nothing
/// is parsed first.
#[derive(Default)]
struct StoreFile {
    bytes: Vec<u8>,
    n: usize,
    next_run: u32,
    keys_at: usize,
    runs_at: usize,
    offsets_at: usize,
    answers_at: usize,
}

/// An entry to write: its key, the number of the run that last wrote or
/// used it, its encoded answers.
type Entry<'a> = (Key, u32, &'a [u8]);

impl StoreFile {
    /// The file's bytes as a store; None if they are not one (then the
    /// store starts empty).
    fn of(bytes: Vec<u8>) -> Option<StoreFile> {
        let keys_at = FORMAT.len() + 1 + 8;
        if !bytes.starts_with(FORMAT.as_bytes()) || bytes.get(FORMAT.len()) != Some(&b'\n') {
            return None;
        }
        let n = u32_at(&bytes, keys_at - 8)? as usize;
        let next_run = u32_at(&bytes, keys_at - 4)?;
        let runs_at = keys_at + 16 * n;
        let offsets_at = runs_at + 4 * n;
        let answers_at = offsets_at + 4 * (n + 1);
        let file = StoreFile {
            n,
            next_run,
            keys_at,
            runs_at,
            offsets_at,
            answers_at,
            bytes,
        };
        // the last offset is the answers' length: a file cut short is none
        let total = file.offset(n)?;
        (file.bytes.len() == answers_at.checked_add(total)?).then_some(file)
    }

    fn key(&self, i: usize) -> Key {
        let at = self.keys_at + 16 * i;
        Key::from_le_bytes(self.bytes[at..at + 16].try_into().unwrap_or_default())
    }

    fn run(&self, i: usize) -> u32 {
        u32_at(&self.bytes, self.runs_at + 4 * i).unwrap_or_default()
    }

    fn offset(&self, i: usize) -> Option<usize> {
        Some(u32_at(&self.bytes, self.offsets_at + 4 * i)? as usize)
    }

    fn answer(&self, i: usize) -> Option<&[u8]> {
        let (a, b) = (self.offset(i)?, self.offset(i + 1)?);
        self.bytes.get(self.answers_at + a..self.answers_at + b)
    }

    /// Where `key` is among the entries.
    fn find(&self, key: Key) -> Option<usize> {
        let (mut lo, mut hi) = (0, self.n);
        while lo < hi {
            let mid = (lo + hi) / 2;
            match self.key(mid).cmp(&key) {
                std::cmp::Ordering::Less => lo = mid + 1,
                std::cmp::Ordering::Greater => hi = mid,
                std::cmp::Ordering::Equal => return Some(mid),
            }
        }
        None
    }

    fn get(&self, key: Key) -> Option<&[u8]> {
        self.answer(self.find(key)?)
    }

    /// The file of `entries` (in increasing key order), the next run
    /// numbered `next_run`.
    fn write(entries: &[Entry], next_run: u32) -> Vec<u8> {
        let total: usize = entries.iter().map(|(_, _, a)| a.len()).sum();
        let mut out = Vec::with_capacity(FORMAT.len() + 9 + 24 * entries.len() + total + 4);
        out.extend_from_slice(FORMAT.as_bytes());
        out.push(b'\n');
        out.extend_from_slice(&(entries.len() as u32).to_le_bytes());
        out.extend_from_slice(&next_run.to_le_bytes());
        for (k, _, _) in entries {
            out.extend_from_slice(&k.to_le_bytes());
        }
        for (_, run, _) in entries {
            out.extend_from_slice(&run.to_le_bytes());
        }
        let mut offset = 0u32;
        out.extend_from_slice(&offset.to_le_bytes());
        for (_, _, a) in entries {
            offset += a.len() as u32;
            out.extend_from_slice(&offset.to_le_bytes());
        }
        for (_, _, a) in entries {
            out.extend_from_slice(a);
        }
        out
    }
}

impl Store {
    /// The entries to write, at most `most`, in key order: the new ones
    /// and the read ones this run used (numbered this run's), then the
    /// others by the run that last wrote or used them, latest first.
    fn kept(&self, most: usize) -> Vec<Entry<'_>> {
        let run = self.read.next_run;
        let mut entries: Vec<Entry> = self
            .new
            .iter()
            .map(|(k, a)| (*k, run, a.as_slice()))
            .collect();
        entries.sort_by_key(|e| e.0);
        entries.truncate(most);
        let read = &self.read;
        let mut others: Vec<Entry> = (0..read.n)
            .filter_map(|i| {
                let last = if self.used[i] { run } else { read.run(i) };
                Some((read.key(i), last, read.answer(i)?))
            })
            .collect();
        let room = most - entries.len();
        if others.len() > room {
            // (a sort that keeps key order among equals)
            others.sort_by_key(|e| std::cmp::Reverse(e.1));
        }
        entries.extend(others.into_iter().take(room));
        entries.sort_by_key(|e| e.0);
        entries
    }
}

static STORE: OnceLock<Option<Mutex<Store>>> = OnceLock::new();
static FOLDER: OnceLock<Option<PathBuf>> = OnceLock::new();

/// Uses the store in `folder` (None: no store) for this process; the
/// first call decides. Without a call the process keeps no answers.
pub fn open(folder: Option<PathBuf>) {
    let _ = FOLDER.set(folder);
}

/// The folder named by `$FREEMESH_ANSWER_STORE`, else the user's cache
/// folder; None with `off` or no such folder.
pub fn default_folder() -> Option<PathBuf> {
    match std::env::var_os("FREEMESH_ANSWER_STORE") {
        Some(v) if v == "off" => None,
        Some(v) if !v.is_empty() => Some(PathBuf::from(v)),
        _ => dirs_next::cache_dir().map(|d| d.join("freemesh")),
    }
}

fn store() -> Option<&'static Mutex<Store>> {
    STORE
        .get_or_init(|| {
            let folder = FOLDER.get()?.as_ref()?;
            let path = folder.join("answers.bin");
            let read = std::fs::read(&path)
                .ok()
                .and_then(StoreFile::of)
                .unwrap_or_default();
            Some(Mutex::new(Store {
                path,
                used: vec![false; read.n],
                read,
                new: HashMap::new(),
            }))
        })
        .as_ref()
}

/// Whether this process keeps answers (`open` named a folder).
pub fn is_open() -> bool {
    store().is_some()
}

/// The state of rules of these texts (the loader's and the built-in
/// files', names and texts in load order) before any bound is changed.
pub fn initial_state(texts: &[&str]) -> Key {
    let mut h = Fnv::new();
    h.add(FORMAT.as_bytes());
    h.add(env!("CARGO_PKG_VERSION").as_bytes());
    h.add(ENGINE.as_bytes());
    for text in texts {
        h.add(text.as_bytes());
    }
    h.0
}

/// The rules' state as the store keys it: the built-in rules and the
/// bounds changed since, a pop of bounds giving back the state of before
/// its push (as it gives back the bounds; else which worker of a run
/// meshed what before would change the keys).
#[derive(Debug, Clone)]
pub struct RulesState {
    now: Key,
    pushed: Vec<Key>,
}

impl RulesState {
    /// The state of rules whose texts give `initial` (`initial_state`).
    pub fn new(initial: Key) -> RulesState {
        RulesState {
            now: initial,
            pushed: Vec::new(),
        }
    }

    /// The key of `query` asked for at most `limit` answers now.
    pub fn key(&self, limit: usize, query: &str) -> Key {
        key(self.now, limit, query)
    }

    /// The state after `change`, a pop of bounds or a push.
    pub fn change(&mut self, change: &str, pop: bool) {
        if pop {
            if let Some(before) = self.pushed.pop() {
                self.now = before;
                return;
            }
        } else {
            self.pushed.push(self.now);
        }
        self.now = after(self.now, change);
    }
}

/// The state after `change` (a query that changes bounds) in `state`.
pub fn after(state: Key, change: &str) -> Key {
    key(state, 0, change)
}

/// The key of `query` asked for at most `limit` answers in `state`.
pub fn key(state: Key, limit: usize, query: &str) -> Key {
    let mut h = Fnv(state);
    h.add(&(limit as u64).to_le_bytes());
    h.add(query.as_bytes());
    h.0
}

/// The answers kept for `key`, if any.
pub fn get(key: Key) -> Option<Vec<Bindings>> {
    let mut store = store()?.lock().ok()?;
    if let Some(i) = store.read.find(key) {
        store.used[i] = true;
        return decode_answers(&mut store.read.answer(i)?);
    }
    decode_answers(&mut store.new.get(&key)?.as_slice())
}

/// Keeps `answers` for `key` (answers holding a number the store does
/// not write exactly are not kept).
pub fn put(key: Key, answers: &[Bindings]) {
    let Some(store) = store() else { return };
    let mut bytes = Vec::new();
    if encode_answers(answers, &mut bytes).is_none() {
        return;
    }
    if let Ok(mut store) = store.lock() {
        if store.read.get(key).is_none() {
            store.new.insert(key, bytes);
        }
    }
}

/// Writes the answers this run found, with those read, to the store's
/// file (through a temporary renamed over it: a reader sees the old file
/// or the new one whole). Says why when it cannot.
pub fn save() -> Result<usize, String> {
    let Some(store) = STORE.get().and_then(Option::as_ref) else {
        return Ok(0);
    };
    let store = store
        .lock()
        .map_err(|_| "the store was poisoned".to_string())?;
    if store.new.is_empty() {
        return Ok(0);
    }
    let out = StoreFile::write(
        &store.kept(MOST_ANSWERS),
        // (never wrapped: a run numbered 0 again would count as the oldest)
        store.read.next_run.saturating_add(1),
    );
    let folder = store.path.parent().ok_or("no folder")?;
    std::fs::create_dir_all(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
    let tmp = store
        .path
        .with_extension(format!("tmp{}", std::process::id()));
    let written = std::fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(&out))
        .and_then(|()| std::fs::rename(&tmp, &store.path));
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(format!("{}: {e}", store.path.display()));
    }
    Ok(store.new.len())
}

/// The little-endian u32 at `at`, if the bytes hold one there.
fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

fn take<'a>(bytes: &mut &'a [u8], n: usize) -> Option<&'a [u8]> {
    if bytes.len() < n {
        return None;
    }
    let (head, tail) = bytes.split_at(n);
    *bytes = tail;
    Some(head)
}

fn encode_answers(answers: &[Bindings], out: &mut Vec<u8>) -> Option<()> {
    put_len(answers.len(), out);
    for b in answers {
        put_len(b.len(), out);
        for (name, t) in b {
            put_text(name, out);
            encode_term(t, out)?;
        }
    }
    Some(())
}

fn decode_answers(bytes: &mut &[u8]) -> Option<Vec<Bindings>> {
    let n = get_len(bytes)?;
    let mut answers = Vec::with_capacity(n);
    for _ in 0..n {
        let m = get_len(bytes)?;
        let mut b = Bindings::new();
        for _ in 0..m {
            let name = get_text(bytes)?;
            b.insert(name, decode_term(bytes)?);
        }
        answers.push(b);
    }
    Some(answers)
}

fn encode_term(t: &Term, out: &mut Vec<u8>) -> Option<()> {
    match t {
        Term::Integer(i) => {
            let i: i64 = i.to_string().parse().ok()?;
            out.push(b'i');
            out.extend_from_slice(&i.to_le_bytes());
        }
        Term::Float(f) => {
            out.push(b'f');
            out.extend_from_slice(&f.to_bits().to_le_bytes());
        }
        Term::Atom(s) | Term::String(s) | Term::Var(s) => {
            out.push(match t {
                Term::Atom(_) => b'a',
                Term::String(_) => b's',
                _ => b'v',
            });
            put_text(s, out);
        }
        Term::List(items) => {
            out.push(b'l');
            put_len(items.len(), out);
            for item in items {
                encode_term(item, out)?;
            }
        }
        Term::Compound(f, args) => {
            out.push(b'c');
            put_text(f, out);
            put_len(args.len(), out);
            for a in args {
                encode_term(a, out)?;
            }
        }
        // a rational is not written: the answer is not kept
        _ => return None,
    }
    Some(())
}

fn decode_term(bytes: &mut &[u8]) -> Option<Term> {
    let tag = take(bytes, 1)?[0];
    Some(match tag {
        b'i' => Term::integer(i64::from_le_bytes(take(bytes, 8)?.try_into().ok()?)),
        b'f' => Term::Float(f64::from_bits(u64::from_le_bytes(
            take(bytes, 8)?.try_into().ok()?,
        ))),
        b'a' => Term::Atom(get_text(bytes)?),
        b's' => Term::String(get_text(bytes)?),
        b'v' => Term::Var(get_text(bytes)?),
        b'l' => {
            let n = get_len(bytes)?;
            Term::List((0..n).map(|_| decode_term(bytes)).collect::<Option<_>>()?)
        }
        b'c' => {
            let f = get_text(bytes)?;
            let n = get_len(bytes)?;
            Term::Compound(
                f,
                (0..n).map(|_| decode_term(bytes)).collect::<Option<_>>()?,
            )
        }
        _ => return None,
    })
}

fn put_len(n: usize, out: &mut Vec<u8>) {
    out.extend_from_slice(&(n as u32).to_le_bytes());
}

fn get_len(bytes: &mut &[u8]) -> Option<usize> {
    Some(u32::from_le_bytes(take(bytes, 4)?.try_into().ok()?) as usize)
}

fn put_text(s: &str, out: &mut Vec<u8>) {
    put_len(s.len(), out);
    out.extend_from_slice(s.as_bytes());
}

fn get_text(bytes: &mut &[u8]) -> Option<String> {
    let n = get_len(bytes)?;
    String::from_utf8(take(bytes, n)?.to_vec()).ok()
}

/// FNV-1a, 128 bits: the same key in every build and on every machine.
struct Fnv(u128);

impl Fnv {
    fn new() -> Fnv {
        Fnv(0x6c62272e07bb014262b821756295c58d)
    }

    fn add(&mut self, bytes: &[u8]) {
        // the length first: ("ab", "c") and ("a", "bc") differ
        for b in (bytes.len() as u64).to_le_bytes().iter().chain(bytes) {
            self.0 ^= *b as u128;
            self.0 = self.0.wrapping_mul(0x0000000001000000000000000000013b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_store_keeps_the_new_answers_the_ones_used_then_the_latest() {
        // keys 0 to 5, last used by runs 1, 3, 2, 3, 0 and 0; this is run 4
        let runs = [1, 3, 2, 3, 0, 0];
        let read: Vec<Entry> = (0..6u128)
            .map(|k| (k, runs[k as usize], &b"r"[..]))
            .collect();
        let read = StoreFile::of(StoreFile::write(&read, 4)).unwrap();
        assert_eq!((0..6).map(|i| read.run(i)).collect::<Vec<_>>(), runs);
        let mut used = vec![false; read.n];
        used[4] = true;
        used[5] = true;
        let store = Store {
            path: PathBuf::new(),
            read,
            new: HashMap::from([(9, b"n".to_vec())]),
            used,
        };
        let keys = |most| store.kept(most).iter().map(|e| e.0).collect::<Vec<_>>();
        assert_eq!(keys(3), [4, 5, 9]);
        // then the latest: runs 3 (keys 1 and 3, in key order), 2, 1
        assert_eq!(keys(4), [1, 4, 5, 9]);
        assert_eq!(keys(5), [1, 3, 4, 5, 9]);
        assert_eq!(keys(6), [1, 2, 3, 4, 5, 9]);
        assert_eq!(keys(1), [9]);
        assert_eq!(keys(10), [0, 1, 2, 3, 4, 5, 9]);
        // what was used or new is this run's
        let kept = store.kept(10);
        let run_of = |k: Key| kept.iter().find(|e| e.0 == k).unwrap().1;
        assert_eq!([run_of(4), run_of(5), run_of(9), run_of(0)], [4, 4, 4, 1]);
    }

    #[test]
    fn an_answer_reads_back_as_it_was_written() {
        let mut b = Bindings::new();
        b.insert(
            "R".into(),
            Term::Compound(
                "d".into(),
                vec![
                    Term::Atom("b2".into()),
                    Term::List(vec![Term::integer(-3), Term::Float(0.1 + 0.2)]),
                    Term::String("x y".into()),
                    Term::Var("_A".into()),
                ],
            ),
        );
        let answers = vec![b, Bindings::new()];
        let mut bytes = Vec::new();
        encode_answers(&answers, &mut bytes).unwrap();
        assert_eq!(decode_answers(&mut &bytes[..]), Some(answers));
    }

    #[test]
    fn a_bound_changed_or_another_limit_is_another_key() {
        let s = initial_state(&["a", "b"]);
        assert_ne!(after(s, "fm_push_bounds([a-1])."), s);
        assert_ne!(key(s, 1, "q."), key(s, 2, "q."));
        assert_ne!(key(s, 1, "q."), key(after(s, "x."), 1, "q."));
        assert_eq!(key(s, 1, "q."), key(initial_state(&["a", "b"]), 1, "q."));
        assert_ne!(s, initial_state(&["a", "b2"]));
    }

    #[test]
    fn the_engine_named_in_the_key_is_the_one_built() {
        let lock = include_str!("../../Cargo.lock");
        let version = ENGINE.strip_prefix("scryer-prolog ").unwrap();
        assert!(lock.contains(&format!(
            "name = \"scryer-prolog\"\nversion = \"{version}\""
        )));
    }

    #[test]
    fn a_pop_gives_back_the_state_of_before_its_push() {
        let mut state = RulesState::new(initial_state(&["a"]));
        let before = state.key(1, "q.");
        state.change("push(a).", false);
        let pushed = state.key(1, "q.");
        state.change("push(b).", false);
        assert_ne!(state.key(1, "q."), pushed);
        state.change("pop.", true);
        assert_eq!(state.key(1, "q."), pushed);
        state.change("pop.", true);
        assert_eq!(state.key(1, "q."), before);
    }

    #[test]
    fn a_store_file_finds_each_of_its_answers_and_no_other() {
        let entries: Vec<Entry> = vec![(3, 7, b"c"), (10, 0, b""), (u128::MAX, 2, b"zz")];
        let file = StoreFile::of(StoreFile::write(&entries, 8)).unwrap();
        for (i, (k, run, a)) in entries.iter().enumerate() {
            assert_eq!(file.get(*k), Some(*a));
            assert_eq!(file.run(i), *run);
        }
        assert_eq!(file.get(4), None);
        assert_eq!(file.next_run, 8);
    }

    #[test]
    fn a_file_cut_short_is_no_store() {
        let whole = StoreFile::write(&[(1, 0, b"abc".as_slice())], 1);
        assert!(StoreFile::of(whole[..whole.len() - 1].to_vec()).is_none());
        assert!(StoreFile::of(whole[..10].to_vec()).is_none());
        assert!(StoreFile::of(b"something else".to_vec()).is_none());
    }
}
