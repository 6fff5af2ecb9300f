//! WGSL sources assembled from their `// requires:` headers: the one resolver every crate's
//! pipelines and the naga test use.
//!
//! A file whose first line is `// requires: a.wgsl b.wgsl` is compiled after those files, in
//! that order (the header names everything it needs, transitively). [`SHARED`] are
//! shadow-core's; other names are the crate's own files.

use super::LIGHT_SPACE_WGSL;

/// The WGSL parts shadow-core shares with every crate: `light_space.wgsl` (projection, biases,
/// bilinear taps) and `seeds.wgsl` (jump-flood seed packing).
pub const SHARED: &[(&str, &str)] = &[
    ("light_space.wgsl", LIGHT_SPACE_WGSL),
    ("seeds.wgsl", include_str!("seeds.wgsl")),
];

/// The files a `// requires:` first line names (none without one).
pub fn requires(source: &str) -> Vec<&str> {
    source
        .lines()
        .next()
        .and_then(|l| l.strip_prefix("// requires:"))
        .map(|l| l.split_whitespace().collect())
        .unwrap_or_default()
}

/// File `name` of `files` (name, source) after the files it requires. A name found in neither
/// `files` nor shadow-core is an error naming it.
pub fn resolve(name: &str, files: &[(&str, &str)]) -> Result<String, String> {
    let find = |n: &str| {
        files
            .iter()
            .find(|(f, _)| *f == n)
            .or_else(|| SHARED.iter().find(|(f, _)| *f == n))
            .map(|(_, s)| *s)
            .ok_or_else(|| format!("WGSL file {n:?} is not among {:?}", names(files)))
    };
    let source = find(name)?;
    let mut parts = requires(source)
        .into_iter()
        .map(find)
        .collect::<Result<Vec<_>, _>>()?;
    parts.push(source);
    Ok(parts.join("\n"))
}

fn names<'a>(files: &[(&'a str, &str)]) -> Vec<&'a str> {
    files.iter().map(|(n, _)| *n).collect()
}

/// [`resolve`] for a crate's own, complete file list: a missing file is a bug of that crate
/// (the naga test resolves every file), so it panics with the resolver's message.
pub fn source(name: &str, files: &[(&str, &str)]) -> String {
    resolve(name, files).unwrap_or_else(|e| panic!("{e}"))
}
