/**
 * @class   vtkRayScopeAccelSource
 * @brief   The acceleration structure of a scene as vtkPolyData boxes: the
 *          bounding volume hierarchy, the kD-tree's cells, the octree's nodes,
 *          or the sphere tree's nodes as spheres.
 *
 * It draws the structure the scene's rays walk (the scene source's Accel):
 * the binary BVH for ACCEL_BVH, ACCEL_BINARY_BVH and ACCEL_NONE (whose rays
 * walk nothing), the kD-tree's cells for ACCEL_KDTREE, the octree's nodes
 * (their loose boxes with smallest-cell storage) for ACCEL_OCTREE, the BSP
 * tree's cells (their bounding boxes) and split planes for ACCEL_BSP, the
 * sphere tree's nodes for ACCEL_SPHERES; node ids are the ones its walk
 * reports, so visit counts and played walks work for each. Field data
 * "Structure" names it ("bvh", "kdtree", "grid", "octree", "bsp",
 * "spheres"). What follows says "node" for a BVH node or a cell, and "box"
 * for its drawing.
 *
 * For the BSP tree, each inner node shown also gets its split plane clipped
 * to its cell, a convex polygon cell with the node's data, after all boxes
 * (the lecture's "BSP planes as clipped polygons").
 *
 * A sphere tree's node is drawn as its sphere, not a box: with GenerateFaces
 * a latitude-longitude surface (24 segments x 12 rings: triangles at the
 * poles, quads between, outward facing), else three great circles in the
 * coordinate planes (24 line cells each). Its cells carry the same data as a
 * box's; "SAHCost" uses the area of the box around the sphere, as for every
 * structure.
 *
 * The scene's datasets come through input port 0 (one or more vtkDataSets),
 * as for vtkRayScopeRayTreeSource, and the camera, sampling and structure
 * from its settings (GetSettings(), shareable with the other RayScope
 * filters; by default its own, with the camera fitted to the data), or from a
 * scene source (SetSceneSource) whose settings, and, with no input connected,
 * inputs are used.
 *
 * Takes the scene of a vtkRayScopeImageAlgorithm (SetSceneSource) and outputs
 * one box per BVH node whose level (root = 0) lies in LevelRange (and, with
 * OnlyLeaves, that is a leaf): 12 line cells per box, or 6 outward-facing quads
 * with GenerateFaces. Every cell of a box carries the node's data:
 *
 * - "Level", "NodeId", "ParentId" (-1 for the root), "IsLeaf";
 * - "PrimitiveCount": primitives in the node's subtree (a leaf's own count;
 *   in a kD-tree a primitive stored in several cells counts in each);
 * - "PrimitiveOffset": a leaf's first slot in the field array
 *   "LeafPrimitiveIds" (-1 for inner nodes); slots offset .. offset+count-1 of
 *   that array hold the leaf's global primitive ids (triangles numbered input
 *   by input, in the order of the converted meshes);
 * - "SAHCost": the node's term of the surface area heuristic, its area
 *   relative to the root's times the traversal cost (inner nodes) or the
 *   intersection cost times its primitive count (leaves); the terms of all
 *   nodes sum to the hierarchy's SAH cost (field data "SAHCostTotal");
 * - "VisitCount": how often rays visited the node: with VisitModeToPixel the
 *   rays of pixel Pixel (VTK image coordinates; all samples, or only the ray
 *   VisitRay of the recorded ray tree, as numbered by vtkRayScopeRayTreeSource),
 *   with VisitModeToFrame every ray of the whole image, 0 with VisitModeToNone.
 *   Counted on the walk renders do: with the default 8-wide walk a ray enters
 *   only the binary nodes at the top of each 8-wide node (and the leaves), so
 *   the nodes an 8-wide node swallows keep a count of 0; with the scene's
 *   binary walk (the scene source's SetAccelToBinaryBvh()) every binary node a
 *   ray reaches is counted.
 *
 * Field data also holds "BVHUsed" (0 when the scene is so small that the
 * tracer tests every primitive instead, in which case no ray visits a node)
 * and "TreeDepth".
 *
 * Pixel is in VTK image coordinates: pixel (0, 0) is the bottom-left pixel
 * (the VTK image convention, as in vtkRayScopeImageAlgorithm's output),
 * unlike the rayscope command, whose (0, 0) is the top-left pixel.
 */
#ifndef vtkRayScopeAccelSource_h
#define vtkRayScopeAccelSource_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkRayScopeSceneFilter.h"

class vtkRayScopeImageAlgorithm;

class RAYSCOPEVTK_EXPORT vtkRayScopeAccelSource : public vtkRayScopeSceneFilter {
 public:
  static vtkRayScopeAccelSource* New();
  vtkTypeMacro(vtkRayScopeAccelSource, vtkRayScopeSceneFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Levels shown, inclusive (default 0 .. VTK_INT_MAX: all).
  vtkSetVector2Macro(LevelRange, int);
  vtkGetVector2Macro(LevelRange, int);
  ///@}

  ///@{
  /// Show leaves only (default off).
  vtkSetMacro(OnlyLeaves, vtkTypeBool);
  vtkGetMacro(OnlyLeaves, vtkTypeBool);
  vtkBooleanMacro(OnlyLeaves, vtkTypeBool);
  ///@}

  ///@{
  /// Leave out the leaves that hold no primitive (default off): a uniform
  /// grid's empty cells, which drawn with the others fill its box, and the
  /// empty leaves of the kD-tree, octree and BSP tree. Played walks
  /// (TraversalSteps) show every node the ray touched, empty or not.
  vtkSetMacro(HideEmptyLeaves, vtkTypeBool);
  vtkGetMacro(HideEmptyLeaves, vtkTypeBool);
  vtkBooleanMacro(HideEmptyLeaves, vtkTypeBool);
  ///@}

  ///@{
  /// A BSP tree as its partition (default off): the split polygons of the
  /// levels shown and the root's box, not the boxes around the other nodes'
  /// cells, which overlap one another (a played walk still shows them: its
  /// states are theirs). No effect on the other structures' boxes, which
  /// have no polygons: only their roots are drawn.
  vtkSetMacro(OnlySplitPlanes, vtkTypeBool);
  vtkGetMacro(OnlySplitPlanes, vtkTypeBool);
  vtkBooleanMacro(OnlySplitPlanes, vtkTypeBool);
  ///@}

  ///@{
  /// Quads (6 per box) instead of lines (12 per box).
  vtkSetMacro(GenerateFaces, vtkTypeBool);
  vtkGetMacro(GenerateFaces, vtkTypeBool);
  vtkBooleanMacro(GenerateFaces, vtkTypeBool);
  ///@}

  ///@{
  /// What "VisitCount" counts.
  enum VisitModes { VISIT_NONE = 0, VISIT_PIXEL = 1, VISIT_FRAME = 2 };
  vtkSetClampMacro(VisitMode, int, VISIT_NONE, VISIT_FRAME);
  vtkGetMacro(VisitMode, int);
  void SetVisitModeToNone() { this->SetVisitMode(VISIT_NONE); }
  void SetVisitModeToPixel() { this->SetVisitMode(VISIT_PIXEL); }
  void SetVisitModeToFrame() { this->SetVisitMode(VISIT_FRAME); }
  ///@}

  ///@{
  /// The pixel of VisitModeToPixel (VTK image coordinates, (0, 0) bottom-left)
  /// and the ray of its ray tree to count (-1: every ray of every sample,
  /// default).
  vtkSetVector2Macro(Pixel, int);
  vtkGetVector2Macro(Pixel, int);
  vtkSetMacro(VisitRay, int);
  vtkGetMacro(VisitRay, int);
  ///@}

  ///@{
  /// Plays the walk of one ray: with VisitModeToPixel and a VisitRay >= 0,
  /// TraversalSteps = N >= 0 outputs only the boxes that ray's walk touched
  /// before it entered its (N+1)-th node (its first N nodes entered, in the
  /// order the recorder logged them, and the boxes tested, missed and culled
  /// on the way), with the cell arrays "TraversalState" (a TraversalStates
  /// value) and "EntryOrder" (k for the k-th node entered, from 0; -1 for
  /// boxes only tested). -1 (default): every node, no traversal arrays.
  /// GetNumberOfTraversalEntries() is the ray's total, after an update.
  vtkSetMacro(TraversalSteps, int);
  vtkGetMacro(TraversalSteps, int);
  vtkGetMacro(NumberOfTraversalEntries, int);
  ///@}

  /// "TraversalState" values.
  enum TraversalStates {
    BOX_HIT = 1,  ///< box tested and hit, node not entered (yet)
    BOX_MISSED = 2,
    ENTERED = 3,
    CULLED = 4,   ///< box hit, then skipped: a closer hit was found (early termination)
    HIT_LEAF = 5  ///< entered leaf holding the primitive the ray hit
  };

 protected:
  vtkRayScopeAccelSource();
  ~vtkRayScopeAccelSource() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  int LevelRange[2];
  vtkTypeBool OnlyLeaves;
  vtkTypeBool HideEmptyLeaves;
  vtkTypeBool OnlySplitPlanes;
  vtkTypeBool GenerateFaces;
  int VisitMode;
  int Pixel[2];
  int VisitRay;
  int TraversalSteps;
  int NumberOfTraversalEntries;

 private:
  vtkRayScopeAccelSource(const vtkRayScopeAccelSource&) = delete;
  void operator=(const vtkRayScopeAccelSource&) = delete;
};

#endif
