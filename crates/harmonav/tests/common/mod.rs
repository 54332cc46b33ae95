//! Floor plans shared by the facade's tests.

#![allow(dead_code)] // each test binary uses part of it

use std::sync::Arc;

use harmonav::{FloorMap, FloorOptions, Vector2};

/// The L room: 4 m arms 1.5 m wide, reflex corner (1.5, 1.5); `h = 0.1` m, so `δ = 0.1` m, and
/// radius + margin 0.2 m, so `W_s` is the walls shrunk by 0.1 m.
pub fn l_room() -> Arc<FloorMap> {
    let v = Vector2::new;
    let room = vec![
        v(0.0, 0.0),
        v(4.0, 0.0),
        v(4.0, 1.5),
        v(1.5, 1.5),
        v(1.5, 4.0),
        v(0.0, 4.0),
    ];
    Arc::new(FloorMap::new(room, vec![], &FloorOptions::new(0.1, 0.2)).unwrap())
}
