//! The rounding of the compact vertex format, shared by its encoder (`compact`) and the
//! ring tables that precompute quantized texture coordinates (`rings`).

/// Adding 2^23 to a float in [0, 2^16) leaves the nearest integer (ties to even) in the
/// low bits of its mantissa; so no float-to-integer conversion is needed, which is a
/// checked, per-lane one in Rust.
pub(crate) const UNORM_MAGIC: f32 = 8_388_608.0;
/// 1.5 x 2^23: the same for integers in (-2^22, 2^22), two's complement in the low bits.
pub(crate) const SNORM_MAGIC: f32 = 12_582_912.0;

/// A texture coordinate in [0, 1] as unorm16, rounded to nearest (ties to even) as the
/// four-lane path does.
#[inline(always)]
pub(crate) fn unorm16(c: f32) -> u16 {
    (c.clamp(0.0, 1.0) * 65535.0 + UNORM_MAGIC).to_bits() as u16
}
