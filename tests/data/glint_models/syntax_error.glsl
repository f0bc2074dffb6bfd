// A model file with a syntax error on line 5.
// glint_model truth=self checks=finite
vec3 glint_D(GlintQuery q) {
  float x = 1.0;
  return vec3(x) +;
}
