#pragma once
// The dress-form model: a scanned or generated mannequin mesh (centimetres, y up, facing +z,
// arms in an A-pose, legs where the form has them) and what calibration derives from it:
// cross-section profiles along the height, landmark heights, and the form's own measurements
// under Valentina names (seed §5.2.1; ARCHITECTURE.md "Dress-form model").
//
// Heads, necks, arms and legs are expected where the form has them: arms are kept out of torso
// circumferences by taking only the slice loops that belong to the torso (arms are separate loops
// below the armpit). A torso dress form on a stand (neck cap, no head, arms or legs, a pole to a
// foot on the floor) is recognised too: its torso is the tall wide part above the stand, its
// shoulder and armpit come from the shape of the torso's top (docs/calibration.md "Torso forms"),
// and it has no crotch.

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/calib/mesh.h"
#include "garmcap/calib/slicer.h"
#include "garmcap/drafts/measurements.h"

namespace garmcap::calib {

/// The JSON sidecar of a form mesh (docs/formats.md "Dress-form sidecar").
struct FormSidecar {
  std::filesystem::path mesh;         // mesh file, resolved against the sidecar's folder
  std::string meshUnits = "cm";       // "mm", "cm", "m" or "in"
  drafts::Measurements measurements;  // cm, Valentina names
  std::map<std::string, double> landmarkHeightsCm;  // optional; keys as FormLandmarks::names()
  std::string name;                                 // optional free text
  std::string orientation;                          // optional free text
  std::string source;                               // optional free text
  std::string checked;                              // optional free text
};

/// Reads a sidecar strictly: unknown or missing fields throw drafts::ParseError naming the file
/// and the field. Required: "mesh", "mesh_units", "units" (= "cm"), "measurements".
FormSidecar readFormSidecar(const std::filesystem::path& path);
void writeFormSidecar(const std::filesystem::path& path, const FormSidecar& sidecar);

/// Resolves a `--form` argument (ARCHITECTURE.md): a sidecar .json, or a mesh whose sidecar is
/// the .json of the same base name, else form.json beside it. Returns the sidecar path.
std::filesystem::path resolveFormSidecar(const std::filesystem::path& formArgument);

/// Cross-section of the form at one height (cm).
struct FormSection {
  double heightCm = 0;
  double circumferenceCm = 0;  // convex-hull perimeter of the torso loops (tape measure); 0 if none
  double widthCm = 0;          // front-view x extent of the torso loops
  double depthCm = 0;          // side-view z extent of the torso loops
  double minXCm = 0, maxXCm = 0;            // torso x extent (front view)
  double totalMinXCm = 0, totalMaxXCm = 0;  // x extent of every loop, arms included
  int loopCount = 0;                        // loops of the whole slice
  int torsoLoopCount = 0;             // loops counted as torso (legs below the crotch count too)
  std::vector<SliceLoop> torsoLoops;  // (x, z) cm
};

/// Landmark heights as mesh y in cm (the floor is the mesh's lowest point). Absent ones are
/// std::nullopt (a torso form has no crotch, an armless one no armpit).
struct FormLandmarks {
  std::optional<double> neckBase, shoulder, armpit, bust, waist, hip, crotch;
  /// Stable names used in JSON: "neck_base", "shoulder", "armpit", "bust", "waist", "hip",
  /// "crotch".
  static const std::vector<std::string>& names();
  std::optional<double> get(const std::string& name) const;
  std::map<std::string, double> toMap() const;
};

struct FormViewSections;  // form_view.cpp: the world sections every FormView of a form samples

/// A loaded dress form. Immutable after construction; safe to share between threads.
class FormModel {
 public:
  /// Builds from a mesh already in centimetres. Throws CalibError kMeshNotClosed when the mesh
  /// has open edges, kMeshUnits when its height is not 30..250 cm, kFormNotRecognised when no
  /// torso is found, and kSidecar when `sidecar` (may be empty) disagrees with the mesh: a
  /// derived circumference or the height more than 2% off, or a landmark height more than 2% of
  /// the form's height off.
  FormModel(TriMesh meshCm, FormSidecar sidecar);

  /// Loads a `--form` argument (see resolveFormSidecar), converting the mesh to cm.
  static FormModel load(const std::filesystem::path& formArgument);

  const TriMesh& mesh() const { return mesh_; }
  const FormSidecar& sidecar() const { return sidecar_; }
  double minYCm() const { return minY_; }
  double maxYCm() const { return maxY_; }
  double heightCm() const { return maxY_ - minY_; }
  /// x and z of the body axis (centre of the hip section), cm.
  double axisXCm() const { return axisX_; }
  double axisZCm() const { return axisZ_; }

  /// The torso cross-section at `heightCm` (arms excluded; below the crotch, the legs).
  FormSection section(double heightCm) const;
  /// Sections every `stepCm` from bottom to top (profiles along the height).
  std::vector<FormSection> profile(double stepCm) const;

  const FormLandmarks& landmarks() const { return landmarks_; }
  /// The lowest height of the torso: the crotch of a form with legs, the flat bottom of a torso
  /// form on a stand, else the form's lowest point. Below it a garment hangs free of the torso.
  double torsoBottomCm() const { return torsoBottom_; }
  /// A form on a stand (a torso form): no crotch, and its torso starts above its lowest point.
  bool isTorsoForm() const { return !landmarks_.crotch && torsoBottom_ > minY_ + 1e-9; }
  /// The form's own measurements under Valentina names (bust_circ, waist_circ, hip_circ,
  /// neck_circ, height, height_* of the landmarks, width_bust/waist/hip, leg_crotch_to_floor).
  const drafts::Measurements& measurements() const { return measurements_; }

  /// A report for `garmcap form --json`: measurements, landmark heights, sidecar values and the
  /// differences, mesh statistics.
  std::string reportJson() const;

  /// The world sections FormView samples (pose-independent), made by the first view of this
  /// form with `make` and kept with the form for every later one: slicing the mesh some 700
  /// times costs far more than a render. Copies share them (the form is immutable). Thread-safe.
  std::shared_ptr<const FormViewSections> viewSections(
      const std::function<std::shared_ptr<const FormViewSections>()>& make) const;

 private:
  void findLandmarks();
  void deriveMeasurements();
  void checkSidecar() const;

  TriMesh mesh_;
  FormSidecar sidecar_;
  double minY_ = 0, maxY_ = 0, axisX_ = 0, axisZ_ = 0, torsoBottom_ = 0;
  FormLandmarks landmarks_;
  std::optional<double> bustPointHeight_;  // front-most point of the chest
  drafts::Measurements measurements_;
  struct ViewSectionsSlot {
    std::once_flag once;
    std::shared_ptr<const FormViewSections> sections;
  };
  std::shared_ptr<ViewSectionsSlot> viewSections_ = std::make_shared<ViewSectionsSlot>();
};

/// Unit factor to centimetres for "mm", "cm", "m", "in"; throws std::invalid_argument.
double unitsToCm(const std::string& units);

}  // namespace garmcap::calib
