//! The operations of a Mitsuba `<transform>` block. Each one multiplies the running transform on the
//! left (`T = op * T`), so the operations apply to a point in document order, as in Mitsuba's
//! `parse_xml` (src/core/xml.cpp).

use glam::{DMat3, DMat4, DVec3};

/// `<translate x y z/>`.
pub fn translate(v: DVec3) -> DMat4 {
    DMat4::from_translation(v)
}

/// `<scale x y z/>`.
pub fn scale(v: DVec3) -> DMat4 {
    DMat4::from_scale(v)
}

/// `<rotate x y z angle/>`: counter-clockwise by `degrees` about the axis (right-handed), as
/// Mitsuba's `Transform4f::rotate`. `None` for a zero axis.
pub fn rotate(axis: DVec3, degrees: f64) -> Option<DMat4> {
    let axis = axis.try_normalize()?;
    Some(DMat4::from_axis_angle(axis, degrees.to_radians()))
}

/// `<lookat origin target up/>`: camera (or object) space to world with +z toward `target`,
/// +y along `up` made orthogonal, and +x = up × z (Mitsuba's `Transform4f::look_at`; x points to
/// the image's left for a sensor). A zero `up` picks any vector orthogonal to the view direction,
/// as Mitsuba does. `None` where origin and target coincide or `up` is parallel to the view.
pub fn look_at(origin: DVec3, target: DVec3, up: DVec3) -> Option<DMat4> {
    let dir = (target - origin).try_normalize()?;
    let up = if up.length_squared() == 0.0 {
        dir.any_orthonormal_pair().0
    } else {
        up
    };
    let left = up.cross(dir).try_normalize()?;
    let new_up = dir.cross(left);
    Some(DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    ))
}

/// `<matrix value="..."/>`: 16 values row by row, or 9 for the upper-left 3x3 (the rest identity).
pub fn matrix(values: &[f64]) -> Option<DMat4> {
    match values.len() {
        16 => Some(DMat4::from_cols_array(values.try_into().ok()?).transpose()),
        9 => Some(DMat4::from_mat3(
            DMat3::from_cols_array(values.try_into().ok()?).transpose(),
        )),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrix_is_row_major() {
        let m = matrix(&[
            1.0, 0.0, 0.0, 5.0, 0.0, 1.0, 0.0, 6.0, 0.0, 0.0, 1.0, 7.0, 0.0, 0.0, 0.0, 1.0,
        ])
        .unwrap();
        assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(5.0, 6.0, 7.0));
        let m3 = matrix(&[0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]).unwrap();
        assert!((m3.transform_point3(DVec3::X) - DVec3::Y).length() < 1e-12);
        assert!(matrix(&[1.0; 12]).is_none());
    }

    #[test]
    fn rotate_is_counter_clockwise_about_the_axis() {
        let r = rotate(DVec3::new(0.0, 0.0, 2.0), 90.0).unwrap();
        assert!((r.transform_point3(DVec3::X) - DVec3::Y).length() < 1e-12);
        assert!(rotate(DVec3::ZERO, 90.0).is_none());
    }

    #[test]
    fn look_at_points_z_at_the_target_and_x_left() {
        let m = look_at(DVec3::new(0.0, 0.0, 4.0), DVec3::ZERO, DVec3::Y).unwrap();
        assert!((m.transform_vector3(DVec3::Z) - DVec3::NEG_Z).length() < 1e-12);
        assert!((m.transform_vector3(DVec3::Y) - DVec3::Y).length() < 1e-12);
        // Looking down -z with y up, the viewer's left is -x; Mitsuba's x is up × dir = -x here.
        assert!((m.transform_vector3(DVec3::X) - DVec3::NEG_X).length() < 1e-12);
        assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(0.0, 0.0, 4.0));
        let free = look_at(DVec3::ZERO, DVec3::Z, DVec3::ZERO).unwrap();
        assert!((free.transform_vector3(DVec3::Z) - DVec3::Z).length() < 1e-12);
        assert!(look_at(DVec3::ZERO, DVec3::Z, DVec3::Z).is_none());
    }
}
