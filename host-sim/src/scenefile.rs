//! Scene files (TOML).
use std::path::Path;

/// Loads a scene file.
pub fn load(path: &Path) -> Result<texcore::scene::Scene, String> {
    Err(format!(
        "{}: scene files are not supported yet",
        path.display()
    ))
}
