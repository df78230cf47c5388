#version 300 es
// The deferred headlight pass (DESIGN.md §1, §4): each G-buffer point is lit by each lamp
// with E = I(H, V) cos(eps) / r^2 in lux. (H, V) are the point's direction in lamp space in
// the lamp's angle system, exactly; I is a bilinear lookup with samples at texel centres and
// zero outside the measured grid. The output is illuminance (R32F).
//
// Built three ways (render/gl_headlight.c inserts "#define HL_PASS n" after the version):
//   0  direct: everything per frame from the G-buffer
//   1  terms: once per scene and camera, lamp u_k's sample coordinates and cos(eps) / r^2
//      per pixel into an RGBA32F texture (x, y: sample coordinates, z: the factor, 0 = dark)
//   2  lookup: per frame, only the bilinear lookups of the terms and the sum
#ifndef HL_PASS
#define HL_PASS 0
#endif
precision highp float;
precision highp int;

uniform highp sampler2D u_pos; // xyz: point (m, vehicle frame), w: albedo
uniform highp sampler2D u_nrm; // xyz: unit normal, w: surface id (0: nothing hit)
uniform highp sampler2D u_lid0; // combined distributions (R32F, cd), row 0 = highest V
uniform highp sampler2D u_lid1;
uniform highp sampler2D u_terms0; // pass 2: the terms of each lamp
uniform highp sampler2D u_terms1;
uniform int u_n_lamps;
uniform int u_k; // pass 1: the lamp whose terms are made
uniform vec3 u_lamp_pos[2]; // lamp positions (m)
uniform mat3 u_lamp_to_lamp[2]; // vehicle frame to lamp space (+x right, +y up, +z axis)
uniform int u_angles[2]; // 0: type A, 1: type B
uniform vec4 u_grid[2]; // h_first_deg, v_last_deg, columns per degree, rows per degree
uniform ivec2 u_grid_size[2]; // samples in H and V

out vec4 o_out;

// Sample coordinates of lamp-space direction d; negative when outside the measured grid.
vec2 sample_coords(int k, vec3 d)
{
	float h, v;
	if (u_angles[k] == 0) {
		h = degrees(atan(d.x, d.z));
		v = degrees(atan(d.y, length(d.xz)));
	} else {
		v = degrees(atan(d.y, d.z));
		h = degrees(atan(d.x, length(d.yz)));
	}
	vec2 f = vec2((h - u_grid[k].x) * u_grid[k].z, (u_grid[k].y - v) * u_grid[k].w);
	vec2 last = vec2(u_grid_size[k] - 1);
	if (any(lessThan(f, vec2(0.0))) || any(greaterThan(f, last)))
		return vec2(-1.0);
	return f;
}

float bilinear(highp sampler2D lid, int k, vec2 f)
{
	ivec2 c = min(ivec2(f), u_grid_size[k] - 2);
	vec2 t = f - vec2(c);
	float s00 = texelFetch(lid, c, 0).r;
	float s01 = texelFetch(lid, c + ivec2(1, 0), 0).r;
	float s10 = texelFetch(lid, c + ivec2(0, 1), 0).r;
	float s11 = texelFetch(lid, c + ivec2(1, 1), 0).r;
	return mix(mix(s00, s01, t.x), mix(s10, s11, t.x), t.y);
}

// Lamp k's terms at point p with normal n: sample coordinates and cos(eps) / r^2 (0: dark).
vec3 terms(int k, vec3 p, vec3 n)
{
	vec3 w = p - u_lamp_pos[k];
	float r2 = dot(w, w);
	if (!(r2 > 0.0))
		return vec3(0.0);
	float cos_eps = -dot(n, w) * inversesqrt(r2);
	vec2 f = sample_coords(k, u_lamp_to_lamp[k] * w);
	if (cos_eps <= 0.0 || f.x < 0.0)
		return vec3(0.0);
	return vec3(f, cos_eps / r2);
}

void main()
{
	ivec2 px = ivec2(gl_FragCoord.xy);
#if HL_PASS == 2
	vec4 t0 = texelFetch(u_terms0, px, 0);
	float e = t0.z > 0.0 ? t0.z * bilinear(u_lid0, 0, t0.xy) : 0.0;
	if (u_n_lamps > 1) {
		vec4 t1 = texelFetch(u_terms1, px, 0);
		e += t1.z > 0.0 ? t1.z * bilinear(u_lid1, 1, t1.xy) : 0.0;
	}
	o_out = vec4(e, 0.0, 0.0, 0.0);
#else
	vec4 n = texelFetch(u_nrm, px, 0);
	vec3 p = texelFetch(u_pos, px, 0).xyz;
#if HL_PASS == 1
	o_out = n.w != 0.0 ? vec4(terms(u_k, p, n.xyz), 0.0) : vec4(0.0);
#else
	float e = 0.0;
	if (n.w != 0.0) {
		vec3 t = terms(0, p, n.xyz);
		e = t.z > 0.0 ? t.z * bilinear(u_lid0, 0, t.xy) : 0.0;
		if (u_n_lamps > 1) {
			t = terms(1, p, n.xyz);
			e += t.z > 0.0 ? t.z * bilinear(u_lid1, 1, t.xy) : 0.0;
		}
	}
	o_out = vec4(e, 0.0, 0.0, 0.0);
#endif
#endif
}
