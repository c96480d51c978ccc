#include "vtkRayScopeMaterial.h"

#include <cmath>

#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkProperty.h"

#include "rayscope/image.h"
#include "rayscope/material.h"

vtkStandardNewMacro(vtkRayScopeMaterial);

vtkRayScopeMaterial::vtkRayScopeMaterial()
    : Color{1.0, 1.0, 1.0},
      Ambient(0.0),
      Diffuse(1.0),
      Specular(0.0),
      SpecularColor{1.0, 1.0, 1.0},
      SpecularPower(1.0),
      Reflectivity(0.0),
      Transparency(0.0),
      IndexOfRefraction(1.5),
      BlinnPhong(1) {}

vtkRayScopeMaterial::~vtkRayScopeMaterial() = default;

vtkInformationKeyMacro(vtkRayScopeMaterial, REFLECTIVITY, Double);
vtkInformationKeyMacro(vtkRayScopeMaterial, INDEX_OF_REFRACTION, Double);

namespace {

vtkInformation* property_info(vtkProperty* p) {
  if (!p->GetInformation()) {
    vtkNew<vtkInformation> info;
    p->SetInformation(info);
  }
  return p->GetInformation();
}

double property_value(vtkProperty* p, vtkInformationDoubleKey* key, double fallback) {
  vtkInformation* info = p ? p->GetInformation() : nullptr;
  return info && info->Has(key) ? info->Get(key) : fallback;
}

}  // namespace

void vtkRayScopeMaterial::SetPropertyReflectivity(vtkProperty* p, double value) {
  if (!p) return;
  property_info(p)->Set(REFLECTIVITY(), value);
  p->Modified();
}

double vtkRayScopeMaterial::GetPropertyReflectivity(vtkProperty* p, double fallback) {
  return property_value(p, REFLECTIVITY(), fallback);
}

void vtkRayScopeMaterial::SetPropertyIndexOfRefraction(vtkProperty* p, double value) {
  if (!p) return;
  property_info(p)->Set(INDEX_OF_REFRACTION(), value);
  p->Modified();
}

double vtkRayScopeMaterial::GetPropertyIndexOfRefraction(vtkProperty* p, double fallback) {
  return property_value(p, INDEX_OF_REFRACTION(), fallback);
}

void vtkRayScopeMaterial::CopyProperty(vtkProperty* p) {
  if (!p) return;
  // vtkProperty::GetColor() is a blend of the ambient, diffuse and specular
  // colors; VTK's shaders use the diffuse color for the diffuse term.
  this->SetColor(p->GetDiffuseColor());
  this->SetAmbient(p->GetAmbient());
  this->SetDiffuse(p->GetDiffuse());
  this->SetSpecular(p->GetSpecular());
  this->SetSpecularColor(p->GetSpecularColor());
  this->SetSpecularPower(p->GetSpecularPower());
  this->SetTransparency(1.0 - p->GetOpacity());
  this->SetReflectivity(GetPropertyReflectivity(p, p->GetMetallic()));
  this->SetIndexOfRefraction(GetPropertyIndexOfRefraction(p, p->GetBaseIOR()));
}

void vtkRayScopeMaterial::DeepCopy(vtkRayScopeMaterial* o) {
  if (!o || o == this) return;
  this->SetColor(o->Color);
  this->SetAmbient(o->Ambient);
  this->SetDiffuse(o->Diffuse);
  this->SetSpecular(o->Specular);
  this->SetSpecularColor(o->SpecularColor);
  this->SetSpecularPower(o->SpecularPower);
  this->SetReflectivity(o->Reflectivity);
  this->SetTransparency(o->Transparency);
  this->SetIndexOfRefraction(o->IndexOfRefraction);
  this->SetBlinnPhong(o->BlinnPhong);
}

std::string vtkRayScopeMaterial::Validate() const {
  auto unit = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; };
  for (int i = 0; i < 3; ++i) {
    if (!unit(this->Color[i])) return "Color components must be in [0, 1]";
    if (!unit(this->SpecularColor[i])) return "SpecularColor components must be in [0, 1]";
  }
  if (!unit(this->Ambient)) return "Ambient must be in [0, 1]";
  if (!unit(this->Diffuse)) return "Diffuse must be in [0, 1]";
  if (!unit(this->Specular)) return "Specular must be in [0, 1]";
  if (!std::isfinite(this->SpecularPower) || this->SpecularPower < 0.0)
    return "SpecularPower must be finite and >= 0";
  if (!unit(this->Reflectivity)) return "Reflectivity must be in [0, 1]";
  if (!unit(this->Transparency)) return "Transparency must be in [0, 1]";
  if (this->Reflectivity + this->Transparency > 1.0)
    return "Reflectivity + Transparency must be <= 1";
  if (!std::isfinite(this->IndexOfRefraction) || this->IndexOfRefraction <= 0.0)
    return "IndexOfRefraction must be finite and > 0";
  return {};
}

rayscope::Material vtkRayScopeMaterial::ToCore() const {
  using rayscope::srgb_to_linear;
  rayscope::Material m;
  m.color = rayscope::Color(srgb_to_linear(this->Color[0]), srgb_to_linear(this->Color[1]),
                            srgb_to_linear(this->Color[2]));
  m.ambient = float(this->Ambient);
  m.diffuse = float(this->Diffuse);
  m.specular = float(this->Specular);
  m.specular_color = rayscope::Color(srgb_to_linear(this->SpecularColor[0]),
                                     srgb_to_linear(this->SpecularColor[1]),
                                     srgb_to_linear(this->SpecularColor[2]));
  m.shininess = float(this->SpecularPower);
  m.reflectivity = float(this->Reflectivity);
  m.transparency = float(this->Transparency);
  m.ior = float(this->IndexOfRefraction);
  m.model = this->BlinnPhong ? rayscope::ShadingModel::BlinnPhong : rayscope::ShadingModel::Phong;
  return m;
}

void vtkRayScopeMaterial::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Color: " << this->Color[0] << " " << this->Color[1] << " " << this->Color[2]
     << "\n";
  os << indent << "Ambient: " << this->Ambient << "\n";
  os << indent << "Diffuse: " << this->Diffuse << "\n";
  os << indent << "Specular: " << this->Specular << "\n";
  os << indent << "SpecularColor: " << this->SpecularColor[0] << " " << this->SpecularColor[1]
     << " " << this->SpecularColor[2] << "\n";
  os << indent << "SpecularPower: " << this->SpecularPower << "\n";
  os << indent << "Reflectivity: " << this->Reflectivity << "\n";
  os << indent << "Transparency: " << this->Transparency << "\n";
  os << indent << "IndexOfRefraction: " << this->IndexOfRefraction << "\n";
  os << indent << "BlinnPhong: " << this->BlinnPhong << "\n";
}
