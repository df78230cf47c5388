/* SPDX-License-Identifier: MIT */
#include "render/pixel.h"

#include <math.h>
#include <string.h>

uint8_t hl_pixel_srgb8(float x)
{
	if (!(x > 0.0f))
		return 0;
	if (x >= 1.0f)
		return 255;
	x = x <= 0.0031308f ? 12.92f * x : 1.055f * powf(x, 1.0f / 2.4f) - 0.055f;
	return (uint8_t)lrintf(255.0f * x);
}

uint8_t hl_pixel_display8(float luminance)
{
	const float x = luminance * (float)M_1_PI;

	return x > 0.0f ? hl_pixel_srgb8(x / (1.0f + x)) : 0;
}

uint16_t hl_pixel_half_from_float(float f)
{
	uint32_t x, sign, mant;
	int32_t exp;

	memcpy(&x, &f, sizeof(x));
	sign = (x >> 16) & 0x8000u;
	exp = (int32_t)((x >> 23) & 0xff) - 127 + 15;
	mant = x & 0x7fffffu;
	if (((x >> 23) & 0xff) == 0xff) /* inf, nan */
		return (uint16_t)(sign | 0x7c00u | (mant ? 0x200u : 0));
	if (exp >= 31)
		return (uint16_t)(sign | 0x7c00u);
	if (exp <= 0) {
		uint32_t m, shift, half, rounded;

		if (exp < -10)
			return (uint16_t)sign;
		m = mant | 0x800000u;
		shift = (uint32_t)(14 - exp);
		half = 1u << (shift - 1);
		rounded = m >> shift;
		if ((m & ((1u << shift) - 1)) > half ||
		    ((m & ((1u << shift) - 1)) == half && (rounded & 1)))
			rounded++;
		return (uint16_t)(sign | rounded);
	}
	{
		uint32_t h = sign | ((uint32_t)exp << 10) | (mant >> 13);
		const uint32_t rest = mant & 0x1fffu;

		/* Round to nearest even; a carry into the exponent is still correct. */
		if (rest > 0x1000u || (rest == 0x1000u && (h & 1)))
			h++;
		return (uint16_t)h;
	}
}

float hl_pixel_half_to_float(uint16_t h)
{
	const uint32_t sign = (uint32_t)(h & 0x8000u) << 16;
	uint32_t exp = (h >> 10) & 0x1f, mant = h & 0x3ffu, x;
	float f;

	if (exp == 0x1f) {
		x = sign | 0x7f800000u | (mant << 13);
	} else if (exp == 0) {
		f = ldexpf((float)mant, -24);
		return sign ? -f : f;
	} else {
		x = sign | ((exp + 112) << 23) | (mant << 13);
	}
	memcpy(&f, &x, sizeof(f));
	return f;
}
