//! Writes the whole OpenGRASP kitchen (static furniture, the nine objects and the ARMAR-III-like
//! humanoid at its start pose) as one Wavefront OBJ file, ready for any 3D viewer.
//!
//! ```text
//! cargo run --example export_kitchen_obj -- [output.obj]   # default: kitchen.obj
//! ```

use opengrasp::assets::export;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "kitchen.obj".to_string());
    let text = export::kitchen_obj()?;
    std::fs::write(&path, &text)?;
    let parts = export::obj_summary(&text);
    let vertices: usize = parts.iter().map(|(_, n)| n).sum();
    println!("wrote {path}: {} objects, {vertices} vertices", parts.len());
    Ok(())
}
