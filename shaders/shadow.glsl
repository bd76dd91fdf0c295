// shadow.glsl - depth of the mesh seen from one light (slope-scaled offset set by the C side).
uniform mat4 u_matrix; // mesh space -> light clip space
#ifdef DM_VERTEX
layout(location = 0) in vec3 a_position;
void main()
{
    gl_Position = u_matrix * vec4(a_position, 1.0);
}
#else
void main()
{
}
#endif
