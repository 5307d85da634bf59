//! Label text for contact sheets: runs' labels fitted to a tile's width (drawn with [`crate::render::draw_text`]).

use crate::render::text_width;

/// `text` shortened with `..` at its end so that it is at most `width` pixels wide.
pub fn fit_text(text: &str, px: f32, width: f32) -> String {
    if text_width(text, px) <= width {
        return text.to_owned();
    }
    let chars: Vec<char> = text.chars().collect();
    for keep in (0..chars.len()).rev() {
        let candidate: String = chars[..keep].iter().collect::<String>() + "..";
        if text_width(&candidate, px) <= width {
            return candidate;
        }
    }
    String::new()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fitting_shortens_too_wide_text() {
        let wide = text_width("material.young=300", 12.0);
        assert!(wide > 60.0 && wide < 160.0, "{wide}");
        let fitted = fit_text("material.young=300", 12.0, wide / 2.0);
        assert!(
            fitted.ends_with("..") && text_width(&fitted, 12.0) <= wide / 2.0,
            "{fitted}"
        );
        assert_eq!(fit_text("ab", 12.0, 100.0), "ab");
    }
}
