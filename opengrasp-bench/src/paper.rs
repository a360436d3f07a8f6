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
