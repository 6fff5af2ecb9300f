//! The names of the scenes of many lamps, apart from the scenes themselves: the catalogue's
//! errors name them, and the room is built from the catalogue's.

/// The scenes of many lamps: name and what it is.
pub const LAMP_SCENES: [(&str, &str); 2] = [
    (
        "night-street",
        "16 lamps of five kinds along a street at night, cars and benches under them, an \
         eye-height camera walking down it",
    ),
    (
        "room-lamps",
        "room-lamp's room lit by its table lamp, a ceiling panel and a reading lamp, the camera \
         walking from a corner",
    ),
];
