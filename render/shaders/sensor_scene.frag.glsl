#version 310 es
// What a sensor sees: the directly lit scene, luminance rho E / pi (cd/m^2) per fragment, E from
// both lamps exactly as the live headlight pass (headlight.frag.glsl) computes it: the point in
// lamp space, H/V in the lamp's angle system, bilinear lookup with samples at texel centres and
// zero outside the grid, E = I cos(eps) / r^2 (lamp_lookup.glsl, inserted after the #version
// line by render/gl_sensor.c). The sky is the clear colour.
centroid in vec3 v_pos;
centroid in vec3 v_nrm;
flat in float v_albedo;
flat in vec4 v_sphere;

out vec4 o_out;

// Illuminance (lux) of lamp k at point p with unit normal n.
float lamp(highp sampler2D lid, int k, vec3 p, vec3 n)
{
	vec3 t = terms(k, p, n);
	return t.z > 0.0 ? t.z * bilinear(lid, k, t.xy) : 0.0;
}

void main()
{
	vec3 p = v_pos, n = normalize(v_nrm);
	if (v_sphere.w != 0.0) {
		// Back onto the true sphere: the triangles are its chords.
		vec3 r = normalize(p - v_sphere.xyz);
		p = v_sphere.xyz + abs(v_sphere.w) * r;
		n = sign(v_sphere.w) * r;
	}
	float e = lamp(u_lid0, 0, p, n);
	if (u_n_lamps > 1)
		e += lamp(u_lid1, 1, p, n);
	o_out = vec4(v_albedo * e * 0.31830988618379067, 0.0, 0.0, 0.0);
}
