// Shared by the fragment shaders that light points with the lamps (headlight.frag.glsl, the
// live pass; sensor_scene.frag.glsl, what a GI sensor sees): hl_shader_compose() inserts it
// after their #version line, so both compute E = I(H, V) cos(eps) / r^2 the same way.
// (H, V) are the point's direction in lamp space in the lamp's angle system, exactly; I is a
// bilinear lookup with samples at texel centres and zero outside the measured grid.
// The uniforms are set by hl_gl_lamp_uniforms() (render/gl_util.c).
precision highp float;
precision highp int;

uniform highp sampler2D u_lid0; // combined distributions (R32F, cd), row 0 = highest V
uniform highp sampler2D u_lid1;
uniform int u_n_lamps;
uniform vec3 u_lamp_pos[2]; // lamp positions (m)
uniform mat3 u_lamp_to_lamp[2]; // vehicle frame to lamp space (+x right, +y up, +z axis)
uniform int u_angles[2]; // 0: type A, 1: type B
uniform vec4 u_grid[2]; // h_first_deg, v_last_deg, columns per degree, rows per degree
uniform ivec2 u_grid_size[2]; // samples in H and V

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
