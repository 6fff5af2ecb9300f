//! Shipped text (the README, docs/, crate docs, comments, CLI output and report pages, which
//! are strings in the code) speaks of the project and its users, not of how it was made.

use std::path::Path;

/// Words and phrases that describe the making of the project rather than the project.
const PROCESS_WORDS: [&str; 5] = [
    "issue",
    "session",
    "sitting",
    "previous release's binary",
    "the guide",
];

/// Folders never scanned: build output, version control, user output and test code.
const SKIPPED_DIRS: [&str; 6] = [
    "target",
    ".git",
    "tests",
    "report",
    ".gl",
    "proptest-regressions",
];

/// The process words in `text`, as whole words (an `s` may follow), case-insensitive.
fn process_words(text: &str) -> Vec<&'static str> {
    let lower = text.to_lowercase();
    let bytes = lower.as_bytes();
    let mut found = Vec::new();
    for w in PROCESS_WORDS {
        let hit = lower.match_indices(w).any(|(i, _)| {
            let before = i.checked_sub(1).map(|j| bytes[j]);
            let mut end = i + w.len();
            if bytes.get(end) == Some(&b's') {
                end += 1;
            }
            let after = bytes.get(end).copied();
            let boundary = |c: Option<u8>| c.is_none_or(|c| !c.is_ascii_alphanumeric());
            boundary(before) && boundary(after)
        });
        if hit {
            found.push(w);
        }
    }
    found
}

fn scan(dir: &Path, hits: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let path = e.path();
        let name = e.file_name().to_string_lossy().to_string();
        if path.is_dir() {
            if !SKIPPED_DIRS.contains(&name.as_str()) {
                scan(&path, hits);
            }
            continue;
        }
        // The licences' own words ("issue tracking systems") are not ours to change.
        if name.starts_with("LICENSE") || name.ends_with("-LICENSE.txt") || name == "tests.rs" {
            continue;
        }
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue; // not text: images, fonts, models
        };
        for (n, line) in text.lines().enumerate() {
            let words = process_words(line);
            if !words.is_empty() {
                hits.push(format!("{}:{}: {words:?}: {line}", path.display(), n + 1));
            }
        }
    }
}

#[test]
fn the_matcher_finds_each_process_word_and_no_longer_word() {
    assert_eq!(
        process_words("see the closing note of the Issue."),
        ["issue"]
    );
    assert_eq!(process_words("two sessions ago"), ["session"]);
    assert_eq!(process_words("in the same sitting"), ["sitting"]);
    assert_eq!(process_words("The guide says"), ["the guide"]);
    assert!(process_words("tissue, issuer, guidelines, the guidewire").is_empty());
}

#[test]
fn shipped_text_speaks_of_the_project_not_of_its_making() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let mut hits = Vec::new();
    scan(root, &mut hits);
    assert!(
        hits.is_empty(),
        "{} lines speak of how the project was made:\n{}",
        hits.len(),
        hits.join("\n")
    );
}
