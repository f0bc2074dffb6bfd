// Orthonormal basis from a unit vector: Frisvad 2012 (Kajs 2022 Listing 4.2)
// in the singularity-free form of Duff et al. 2017 ("Building an Orthonormal
// Basis, Revisited", Listing 3): the sign of n.z selects the branch, so
// n = -z is as accurate as n = +z (the 2012 threshold version loses all
// precision for n.z just above -0.9999999). The one implementation in the
// shader tree. Right-handed: cross(b1, b2) = n.
#ifndef GLINTLAB_COMMON_FRISVAD_GLSL
#define GLINTLAB_COMMON_FRISVAD_GLSL

void frisvad_basis(vec3 n, out vec3 b1, out vec3 b2) {
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);  // |s + n.z| >= 1
  float b = n.x * n.y * a;
  b1 = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
  b2 = vec3(b, s + n.y * n.y * a, -n.y);
}

#endif  // GLINTLAB_COMMON_FRISVAD_GLSL
