#version 300 es
// The deferred headlight pass (docs/design.md §1, §4): each G-buffer point is lit by each lamp
// with E = I(H, V) cos(eps) / r^2 in lux. (H, V) are the point's direction in lamp space in
// the lamp's angle system, exactly; I is a bilinear lookup with samples at texel centres and
// zero outside the measured grid. The output is illuminance (R32F).
//
// The lamp lookup is lamp_lookup.glsl, inserted after the #version line with
// "#define HL_PASS n" by render/gl_headlight.c. Built three ways:
//   0  direct: everything per frame from the G-buffer
//   1  terms: once per scene and camera, lamp u_k's sample coordinates and cos(eps) / r^2
//      per pixel into an RGBA32F texture (x, y: sample coordinates, z: the factor, 0 = dark)
//   2  lookup: per frame, only the bilinear lookups of the terms and the sum
#ifndef HL_PASS
#define HL_PASS 0
#endif
uniform highp sampler2D u_pos; // xyz: point (m, vehicle frame), w: albedo
uniform highp sampler2D u_nrm; // xyz: unit normal, w: surface id (0: nothing hit)
uniform highp sampler2D u_terms0; // pass 2: the terms of each lamp
uniform highp sampler2D u_terms1;
uniform int u_k; // pass 1: the lamp whose terms are made

out vec4 o_out;

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
