#version 300 es
// The deferred headlight pass (DESIGN.md §1, §4): each G-buffer point is lit by each lamp
// with E = I(H, V) cos(eps) / r^2 in lux. (H, V) are the point's direction in lamp space in
// the lamp's angle system, exactly; I is a bilinear lookup with samples at texel centres and
// zero outside the measured grid. The output is illuminance (R32F).
precision highp float;
precision highp int;

uniform highp sampler2D u_pos; // xyz: point (m, vehicle frame), w: albedo
uniform highp sampler2D u_nrm; // xyz: unit normal, w: surface id (0: nothing hit)
uniform highp sampler2D u_lid0; // combined distributions (R32F, cd), row 0 = highest V
uniform highp sampler2D u_lid1;
uniform int u_n_lamps;
uniform vec3 u_lamp_pos[2]; // lamp positions (m)
uniform mat3 u_lamp_to_lamp[2]; // vehicle frame to lamp space (+x right, +y up, +z axis)
uniform int u_angles[2]; // 0: type A, 1: type B
uniform vec4 u_grid[2]; // h_first_deg, v_last_deg, columns per degree, rows per degree
uniform ivec2 u_grid_size[2]; // samples in H and V

out vec4 o_lux;

float lookup(highp sampler2D lid, int k, vec3 d)
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
		return 0.0;
	ivec2 c = min(ivec2(f), u_grid_size[k] - 2);
	vec2 t = f - vec2(c);
	float s00 = texelFetch(lid, c, 0).r;
	float s01 = texelFetch(lid, c + ivec2(1, 0), 0).r;
	float s10 = texelFetch(lid, c + ivec2(0, 1), 0).r;
	float s11 = texelFetch(lid, c + ivec2(1, 1), 0).r;
	return mix(mix(s00, s01, t.x), mix(s10, s11, t.x), t.y);
}

float lamp(highp sampler2D lid, int k, vec3 p, vec3 n)
{
	vec3 w = p - u_lamp_pos[k];
	float r2 = dot(w, w);
	float cos_eps = -dot(n, w) * inversesqrt(r2);
	if (!(r2 > 0.0) || cos_eps <= 0.0)
		return 0.0;
	return lookup(lid, k, u_lamp_to_lamp[k] * w) * cos_eps / r2;
}

void main()
{
	ivec2 px = ivec2(gl_FragCoord.xy);
	vec4 n = texelFetch(u_nrm, px, 0);
	float e = 0.0;
	if (n.w != 0.0) {
		vec3 p = texelFetch(u_pos, px, 0).xyz;
		e = lamp(u_lid0, 0, p, n.xyz);
		if (u_n_lamps > 1)
			e += lamp(u_lid1, 1, p, n.xyz);
	}
	o_lux = vec4(e, 0.0, 0.0, 0.0);
}
