// The tone-mapping shader (see tone_shader.h), as replacements in VTK's polydata shader templates.
#include "tone_shader.h"

#include <vtkDataObject.h>
#include <vtkOpenGLPolyDataMapper.h>
#include <vtkShaderProperty.h>
#include <vtkUniforms.h>

namespace view {

namespace {

// Reinhard then sRGB, as hr::toneMap8; the framebuffer's 8 bits round as toneMap8 does.
const char* kToneImpl = R"(
  vec3 radiance = diffuseRadianceVSOut + glossyWeight * glossyRadianceVSOut;
  if (!gl_FrontFacing) radiance = vec3(0.0);
  vec3 x = max(radiance, vec3(0.0)) * exposure;
  x = x / (1.0 + x);
  vec3 srgb = mix(1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055, 12.92 * x, vec3(lessThanEqual(x, vec3(0.0031308))));
  gl_FragData[0] = vec4(clamp(srgb, 0.0, 1.0), 1.0);
)";

}  // namespace

void installToneShader(vtkActor* actor, bool glossy, double exposure) {
  auto* mapper = vtkOpenGLPolyDataMapper::SafeDownCast(actor->GetMapper());
  mapper->ScalarVisibilityOff();
  mapper->MapDataArrayToVertexAttribute("diffuseRadiance", "diffuse_radiance", vtkDataObject::FIELD_ASSOCIATION_POINTS, -1);
  if (glossy)
    mapper->MapDataArrayToVertexAttribute("glossyRadiance", "glossy_radiance", vtkDataObject::FIELD_ASSOCIATION_POINTS, -1);
  vtkShaderProperty* sp = actor->GetShaderProperty();
  std::string vsDec = "//VTK::Color::Dec\nin vec3 diffuseRadiance;\nout vec3 diffuseRadianceVSOut;\n";
  std::string vsImpl = "//VTK::Color::Impl\n  diffuseRadianceVSOut = diffuseRadiance;\n";
  std::string fsDec = "//VTK::Color::Dec\nin vec3 diffuseRadianceVSOut;\n";
  if (glossy) {
    vsDec += "in vec3 glossyRadiance;\nout vec3 glossyRadianceVSOut;\n";
    vsImpl += "  glossyRadianceVSOut = glossyRadiance;\n";
    fsDec += "in vec3 glossyRadianceVSOut;\n";
  } else {
    fsDec += "const vec3 glossyRadianceVSOut = vec3(0.0);\n";
  }
  sp->AddVertexShaderReplacement("//VTK::Color::Dec", true, vsDec, false);
  sp->AddVertexShaderReplacement("//VTK::Color::Impl", true, vsImpl, false);
  sp->AddFragmentShaderReplacement("//VTK::Color::Dec", true, fsDec, false);
  sp->AddFragmentShaderReplacement("//VTK::Light::Impl", true, kToneImpl, false);
  setExposure(actor, exposure);
  setGlossyWeight(actor, 1.0);
}

void setExposure(vtkActor* actor, double exposure) {
  actor->GetShaderProperty()->GetFragmentCustomUniforms()->SetUniformf("exposure", static_cast<float>(exposure));
}

void setGlossyWeight(vtkActor* actor, double weight) {
  actor->GetShaderProperty()->GetFragmentCustomUniforms()->SetUniformf("glossyWeight", static_cast<float>(weight));
}

}  // namespace view
