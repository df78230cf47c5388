#version 300 es
// One light source, weighted by its relative current (or the change of it), added by the
// blender into the lamp's 32-bit float distribution. The viewport is the source's box.
precision highp float;
precision highp int;

uniform highp sampler2D u_src; // the source over its box (R32F, cd at full current)
uniform ivec2 u_origin; // the box's first sample in the distribution
uniform float u_weight; // i_k, or i_new - i_old for an incremental update

out vec4 o_cd;

void main()
{
	ivec2 t = ivec2(gl_FragCoord.xy) - u_origin;
	o_cd = vec4(u_weight * texelFetch(u_src, t, 0).r, 0.0, 0.0, 0.0);
}
