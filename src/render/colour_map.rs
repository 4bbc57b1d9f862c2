//! Colour maps for scalar fields (curvature, scallop height, deviation): piecewise-linear ramps
//! sampled into a 256-texel sRGB texture.

/// A colour map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ColourMap {
    /// Perceptually uniform, dark blue → green → yellow (matplotlib's viridis).
    #[default]
    Viridis,
    /// Rainbow-like with good contrast (Google's turbo).
    Turbo,
    /// Diverging blue → white → red, for signed values (deviation).
    CoolWarm,
    /// A tolerance band for signed values mapped over ±2 × the tolerance: the middle half (within
    /// tolerance) runs light blue → white → light orange; the outer quarters are flat, saturated
    /// out-of-band colours (violet below, red above), so anything out of tolerance stands out
    /// however little it is out.
    Band,
}

/// Out-of-band colour below the band of [`ColourMap::Band`] (sRGB).
pub const BAND_BELOW: [u8; 3] = [110, 40, 200];
/// Out-of-band colour above the band of [`ColourMap::Band`] (sRGB).
pub const BAND_ABOVE: [u8; 3] = [215, 30, 40];

/// Texels across a colour-map texture.
pub const COLOUR_MAP_TEXELS: usize = 256;

impl ColourMap {
    /// Every map, texture row order.
    pub const ALL: [Self; 4] = [Self::Viridis, Self::Turbo, Self::CoolWarm, Self::Band];

    /// Control points (sRGB), evenly spaced over 0..1.
    fn stops(self) -> &'static [[u8; 3]] {
        match self {
            Self::Viridis => &[
                [68, 1, 84],
                [72, 40, 120],
                [62, 74, 137],
                [49, 104, 142],
                [38, 130, 142],
                [31, 158, 137],
                [53, 183, 121],
                [109, 205, 89],
                [180, 222, 44],
                [253, 231, 37],
            ],
            Self::Turbo => &[
                [48, 18, 59],
                [70, 107, 227],
                [40, 187, 236],
                [50, 242, 152],
                [164, 252, 60],
                [237, 208, 58],
                [251, 128, 34],
                [208, 47, 5],
                [122, 4, 3],
            ],
            Self::CoolWarm => &[
                [59, 76, 192],
                [141, 176, 254],
                [221, 221, 221],
                [244, 154, 123],
                [180, 4, 38],
            ],
            // The in-band part of the band map (see `sample`).
            Self::Band => &[[120, 175, 250], [235, 235, 235], [250, 185, 110]],
        }
    }

    /// The colour (sRGB) at `t` in 0..1 (clamped; NaN gives the start).
    #[must_use]
    pub fn sample(self, t: f32) -> [u8; 3] {
        let stops = self.stops();
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let t = if self == Self::Band {
            if t < 0.25 {
                return BAND_BELOW;
            }
            if t > 0.75 {
                return BAND_ABOVE;
            }
            2.0 * (t - 0.25)
        } else {
            t
        };
        let x = t * (stops.len() - 1) as f32;
        let i = (x.floor() as usize).min(stops.len() - 2);
        let f = x - i as f32;
        let (a, b) = (stops[i], stops[i + 1]);
        std::array::from_fn(|k| {
            (f32::from(a[k]) + (f32::from(b[k]) - f32::from(a[k])) * f).round() as u8
        })
    }

    /// The 256 texels (RGBA, sRGB) of this map.
    #[must_use]
    pub fn texels(self) -> Vec<u8> {
        (0..COLOUR_MAP_TEXELS)
            .flat_map(|i| {
                let [r, g, b] = self.sample(i as f32 / (COLOUR_MAP_TEXELS - 1) as f32);
                [r, g, b, 255]
            })
            .collect()
    }

    /// Row of this map in the colour-map texture.
    #[must_use]
    pub fn row(self) -> u32 {
        match self {
            Self::Viridis => 0,
            Self::Turbo => 1,
            Self::CoolWarm => 2,
            Self::Band => 3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_are_the_published_end_colours() {
        assert_eq!(ColourMap::Viridis.sample(0.0), [68, 1, 84]);
        assert_eq!(ColourMap::Viridis.sample(1.0), [253, 231, 37]);
        assert_eq!(ColourMap::Turbo.sample(2.0), [122, 4, 3]);
        assert_eq!(ColourMap::CoolWarm.sample(0.5), [221, 221, 221]);
        assert_eq!(ColourMap::Viridis.texels().len(), 4 * COLOUR_MAP_TEXELS);
    }

    #[test]
    fn the_band_map_is_flat_out_of_band_and_graded_inside() {
        let m = ColourMap::Band;
        // Mapped over ±2 tol: t = 0.25 and 0.75 are −tol and +tol.
        assert_eq!(m.sample(0.0), BAND_BELOW);
        assert_eq!(m.sample(0.24), BAND_BELOW);
        assert_eq!(m.sample(0.76), BAND_ABOVE);
        assert_eq!(m.sample(1.0), BAND_ABOVE);
        assert_eq!(m.sample(0.25), [120, 175, 250]);
        assert_eq!(m.sample(0.5), [235, 235, 235]);
        assert_eq!(m.sample(0.75), [250, 185, 110]);
        for (i, map) in ColourMap::ALL.iter().enumerate() {
            assert_eq!(map.row() as usize, i);
        }
    }
}
