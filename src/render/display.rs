//! How radiance becomes a picture: exposure (stops), then the tonemap, then
//! sRGB; and, in the viewer, the layout. Display and export only: the
//! estimators and the film never see these.

use serde::{Deserialize, Serialize};

use crate::course::options::closed_set;

closed_set! {
    /// The curve that maps exposed radiance to display values (display and PNG only).
    pub enum Tonemap {
        /// Clamp to [0, 1].
        #[default]
        None,
        /// c / (1 + c) per channel.
        Reinhard,
        /// Narkowicz's fit of the ACES filmic curve.
        Aces,
    }
}

impl Tonemap {
    /// The curve applied to one exposed linear value; the result is in [0, 1].
    pub fn apply(self, c: f32) -> f32 {
        let c = c.max(0.0);
        let mapped = match self {
            Tonemap::None => c,
            Tonemap::Reinhard => c / (1.0 + c),
            Tonemap::Aces => (c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14),
        };
        mapped.clamp(0.0, 1.0)
    }
}

closed_set! {
    /// How the viewer lays the image out.
    pub enum Layout {
        /// The sum of the visible terms.
        #[default]
        Single,
        /// L0 | L1 | L2 | their sum, side by side, from the same render
        /// (`crate::render::four_up`).
        FourUp,
    }
}

/// How radiance becomes a picture: exposure (stops), then the tonemap, then
/// sRGB; and, in the viewer, the layout.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DisplaySettings {
    pub exposure: f32,
    pub tonemap: Tonemap,
    /// The viewer's layout (renders and EXR files show the sum).
    pub layout: Layout,
}
