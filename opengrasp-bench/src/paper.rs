//! The OpenGRASP paper's published figures (Ulbrich et al. 2011), printed beside ours.

/// The eight objects of the paper's Tables I and II: `(row label, asset name)`.
pub const PAPER_OBJECTS: [(&str, &str); 8] = [
    ("Bread box", "bread_box"),
    ("Prismatic box", "chocolate_box"),
    ("Salt box", "salt_box"),
    ("Salt can", "salt_can"),
    ("Detergent", "detergent_bottle"),
    ("Spray", "spray_bottle"),
    ("White cup", "white_cup"),
    ("Green cup", "green_cup"),
];

/// The paper's numbers: `(object, hand, planner, candidates, FC %)`, hands `"armar3"` (Table I)
/// and `"barrett"` (Table II), planners `"medial-axis"` and `"surface-normals"`.
pub const PAPER_RESULTS: [(&str, &str, &str, usize, f64); 32] = [
    ("bread_box", "armar3", "medial-axis", 296, 99.0),
    ("bread_box", "armar3", "surface-normals", 842, 16.5),
    ("chocolate_box", "armar3", "medial-axis", 516, 99.8),
    ("chocolate_box", "armar3", "surface-normals", 520, 43.8),
    ("salt_box", "armar3", "medial-axis", 408, 85.8),
    ("salt_box", "armar3", "surface-normals", 408, 41.2),
    ("salt_can", "armar3", "medial-axis", 1072, 80.0),
    ("salt_can", "armar3", "surface-normals", 616, 48.4),
    ("detergent_bottle", "armar3", "medial-axis", 1022, 87.6),
    ("detergent_bottle", "armar3", "surface-normals", 928, 38.5),
    ("spray_bottle", "armar3", "medial-axis", 590, 77.5),
    ("spray_bottle", "armar3", "surface-normals", 762, 29.5),
    ("white_cup", "armar3", "medial-axis", 732, 81.1),
    ("white_cup", "armar3", "surface-normals", 456, 48.2),
    ("green_cup", "armar3", "medial-axis", 514, 51.8),
    ("green_cup", "armar3", "surface-normals", 496, 52.0),
    ("bread_box", "barrett", "medial-axis", 296, 66.9),
    ("bread_box", "barrett", "surface-normals", 842, 11.8),
    ("chocolate_box", "barrett", "medial-axis", 516, 20.2),
    ("chocolate_box", "barrett", "surface-normals", 520, 19.2),
    ("salt_box", "barrett", "medial-axis", 408, 94.4),
    ("salt_box", "barrett", "surface-normals", 408, 47.3),
    ("salt_can", "barrett", "medial-axis", 1072, 91.4),
    ("salt_can", "barrett", "surface-normals", 616, 44.2),
    ("detergent_bottle", "barrett", "medial-axis", 1022, 49.5),
    ("detergent_bottle", "barrett", "surface-normals", 928, 25.8),
    ("spray_bottle", "barrett", "medial-axis", 590, 44.1),
    ("spray_bottle", "barrett", "surface-normals", 762, 13.9),
    ("white_cup", "barrett", "medial-axis", 732, 63.8),
    ("white_cup", "barrett", "surface-normals", 456, 37.5),
    ("green_cup", "barrett", "medial-axis", 514, 34.8),
    ("green_cup", "barrett", "surface-normals", 496, 36.1),
];

/// The paper's Table III (first motion planning scene, its reference planner under its
/// protocol: step 0.05, shortcutting, re-check at a tiny step): average setup, planning and
/// post-processing times (s), valid % of planned and post-processed paths, C-space lengths and
/// mean clearances (mm).
pub struct PaperTableIII {
    /// Average setup time (s), "including loading and data preparation".
    pub setup: f64,
    /// Average planning time (s).
    pub planning: f64,
    /// Average post-processing time (s).
    pub postprocessing: f64,
    /// Planned paths valid under the fine re-check (%).
    pub valid_planned: f64,
    /// Post-processed paths valid under the fine re-check (%).
    pub valid_processed: f64,
    /// Mean C-space length of planned paths.
    pub length_planned: f64,
    /// Mean C-space length of post-processed paths.
    pub length_processed: f64,
    /// Mean clearance of planned paths (mm).
    pub clearance_planned: f64,
    /// Mean clearance of post-processed paths (mm).
    pub clearance_processed: f64,
}

/// Table III of the paper.
pub const PAPER_TABLE_III: PaperTableIII = PaperTableIII {
    setup: 1.44,
    planning: 0.41,
    postprocessing: 1.17,
    valid_planned: 98.1,
    valid_processed: 76.92,
    length_planned: 6.73,
    length_processed: 2.85,
    clearance_planned: 111.12,
    clearance_processed: 44.29,
};

/// The scene of ours that stands for the paper's first motion planning scene.
pub const PAPER_SCENE_1: &str = "standard (ARMAR-III kitchen)";
