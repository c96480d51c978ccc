/**
 * @class   vtkRayScopeMaterial
 * @brief   Surface material of a ray-traced dataset.
 *
 * The Phong/Blinn-Phong coefficients of vtkProperty (color, ambient, diffuse,
 * specular, specular color and power) plus what a ray tracer adds: the weight
 * of the mirror reflection (Reflectivity), the weight of the dielectric
 * (Fresnel-split reflection and refraction, Transparency) and its index of
 * refraction. Colors are given as VTK shows them (sRGB-encoded values in
 * [0, 1]) and decoded to linear RGB for the core. The local (Phong) terms are
 * scaled by 1 - Reflectivity - Transparency, so the two must sum to at most 1.
 *
 * Defaults are vtkProperty's (white, ambient 0, diffuse 1, specular 0, power 1,
 * Blinn-Phong as VTK's OpenGL shaders), with no reflection or transparency and
 * index of refraction 1.5 (glass).
 *
 * The values are checked by the algorithms that use them (vtkErrorMacro naming
 * the field), not clamped here.
 */
#ifndef vtkRayScopeMaterial_h
#define vtkRayScopeMaterial_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkObject.h"

#include <string>  // std::string

class vtkInformationDoubleKey;
class vtkProperty;

#ifndef __VTK_WRAP__
namespace rayscope {
struct Material;
}
#endif

class RAYSCOPEVTK_EXPORT vtkRayScopeMaterial : public vtkObject {
 public:
  static vtkRayScopeMaterial* New();
  vtkTypeMacro(vtkRayScopeMaterial, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Diffuse and ambient color (sRGB, as vtkProperty::SetColor). Default white.
  vtkSetVector3Macro(Color, double);
  vtkGetVector3Macro(Color, double);
  ///@}

  ///@{
  /// Phong coefficients, each in [0, 1].
  vtkSetMacro(Ambient, double);
  vtkGetMacro(Ambient, double);
  vtkSetMacro(Diffuse, double);
  vtkGetMacro(Diffuse, double);
  vtkSetMacro(Specular, double);
  vtkGetMacro(Specular, double);
  ///@}

  ///@{
  /// Specular color (sRGB) and exponent (>= 0).
  vtkSetVector3Macro(SpecularColor, double);
  vtkGetVector3Macro(SpecularColor, double);
  vtkSetMacro(SpecularPower, double);
  vtkGetMacro(SpecularPower, double);
  ///@}

  ///@{
  /// Weight of the mirror reflection, in [0, 1].
  vtkSetMacro(Reflectivity, double);
  vtkGetMacro(Reflectivity, double);
  ///@}

  ///@{
  /// Weight of the dielectric (reflection and refraction split by Fresnel), in
  /// [0, 1]. CopyProperty() sets it to 1 - opacity.
  vtkSetMacro(Transparency, double);
  vtkGetMacro(Transparency, double);
  ///@}

  ///@{
  /// Index of refraction of the inside (> 0; 1.5 by default).
  vtkSetMacro(IndexOfRefraction, double);
  vtkGetMacro(IndexOfRefraction, double);
  ///@}

  ///@{
  /// Blinn-Phong (the half-vector model of VTK's OpenGL shaders, default) or
  /// Phong (reflected light vector) specular highlights.
  vtkSetMacro(BlinnPhong, vtkTypeBool);
  vtkGetMacro(BlinnPhong, vtkTypeBool);
  vtkBooleanMacro(BlinnPhong, vtkTypeBool);
  ///@}

  /// Takes color (the diffuse color), ambient, diffuse, specular (color,
  /// power) from a vtkProperty and Transparency = 1 - opacity. Reflectivity
  /// and the index of refraction come from the property's information keys
  /// REFLECTIVITY() and INDEX_OF_REFRACTION() when it has them (see
  /// SetPropertyReflectivity()), else from its physically based terms: a
  /// smooth metallic surface is a mirror, so reflectivity is Metallic, and
  /// the index of refraction is BaseIOR (vtkProperty's defaults, 0 and 1.5,
  /// are RayScope's). ParaView shows both per representation (Metallic and
  /// Base IOR, advanced properties of Surface), so the RayScope view takes
  /// them from each representation.
  void CopyProperty(vtkProperty* property);

  ///@{
  /// What vtkProperty lacks for ray tracing, stored in its information
  /// (vtkProperty::GetInformation()) so that a renderer's actors carry it:
  /// vtkRayScopeRenderPass and vtkRayScopeImageAlgorithm::CopyRenderer() read
  /// it. The setters create the information object when needed; the getters
  /// return `fallback` for a property without the key.
  static vtkInformationDoubleKey* REFLECTIVITY();
  static vtkInformationDoubleKey* INDEX_OF_REFRACTION();
  static void SetPropertyReflectivity(vtkProperty* property, double reflectivity);
  static double GetPropertyReflectivity(vtkProperty* property, double fallback = 0.0);
  static void SetPropertyIndexOfRefraction(vtkProperty* property, double ior);
  static double GetPropertyIndexOfRefraction(vtkProperty* property, double fallback = 1.5);
  ///@}

  /// Copies every value of another material.
  void DeepCopy(vtkRayScopeMaterial* other);

  /// Empty when the values are valid, else a message naming the first bad one.
  std::string Validate() const;

#ifndef __VTK_WRAP__
  /// The core material (linear colors). Call Validate() first.
  rayscope::Material ToCore() const;
#endif

 protected:
  vtkRayScopeMaterial();
  ~vtkRayScopeMaterial() override;

  double Color[3];
  double Ambient;
  double Diffuse;
  double Specular;
  double SpecularColor[3];
  double SpecularPower;
  double Reflectivity;
  double Transparency;
  double IndexOfRefraction;
  vtkTypeBool BlinnPhong;

 private:
  vtkRayScopeMaterial(const vtkRayScopeMaterial&) = delete;
  void operator=(const vtkRayScopeMaterial&) = delete;
};

#endif
