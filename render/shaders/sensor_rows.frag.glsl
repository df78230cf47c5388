#version 310 es
// First half of the reduction of the sensor maps (render/gl_sensor.c): fragment (tx, y) sums
// row y of the atlas over the tile in column tx, each texel's mean over its samples times its
// projected solid angle F (render/hemicube.h). Short loops: one tile row per fragment.
precision highp float;
precision highp int;

uniform highp sampler2DMS u_atlas; // the sensor maps, luminance (cd/m^2)
uniform highp sampler2D u_weights; // one tile of weights (sr)
uniform int u_samples; // samples per texel of the atlas
uniform ivec2 u_tile; // tile size, texels

out vec4 o_out;

void main()
{
	ivec2 px = ivec2(gl_FragCoord.xy);
	int x0 = px.x * u_tile.x, wy = px.y % u_tile.y;
	float e = 0.0;
	for (int x = 0; x < u_tile.x; x++) {
		float l = 0.0;
		for (int i = 0; i < u_samples; i++)
			l += texelFetch(u_atlas, ivec2(x0 + x, px.y), i).r;
		e += l * texelFetch(u_weights, ivec2(x, wy), 0).r;
	}
	o_out = vec4(e / float(u_samples), 0.0, 0.0, 0.0);
}
