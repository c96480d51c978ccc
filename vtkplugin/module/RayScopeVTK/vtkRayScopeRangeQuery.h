/**
 * @class   vtkRayScopeRangeQuery
 * @brief   The objects of a scene within a range (a box, a sphere, or the k
 *          nearest to a point) as vtkPolyData, found through the scene's
 *          acceleration structure.
 *
 * The lecture's range query (rayscope/range_query.h): the walk of the
 * structure the scene source chose (its Accel: BVH, kD-tree, grid, octree,
 * ... or none), pruning every node whose bound the range misses, with exact
 * object tests, so that every structure finds the same objects. The same
 * query as `rayscope query`.
 *
 * The scene's datasets come through input port 0 (one or more vtkDataSets),
 * as for vtkRayScopeAccelSource; the structure is its settings' Accel
 * (GetSettings(), shareable; the BVH by default) or its scene source's
 * (SetSceneSource).
 *
 * Ranges are in world coordinates:
 * - QueryTypeToBox: every object that shares a point with the closed box
 *   Box = (xmin, xmax, ymin, ymax, zmin, zmax) (VTK's bounds order);
 * - QueryTypeToSphere: every object within distance Radius of Center;
 * - QueryTypeToNearest: the NumberOfNeighbors objects nearest to Center
 *   (all of them when the scene has fewer).
 *
 * Output port 0, the objects found, in the order the query returns them
 * (box: primitives by id, then planes; sphere and nearest: nearest first):
 * a triangle as one triangle cell, an analytic sphere or a point drawn as a
 * sphere as a tessellated sphere (SphereResolution), a tube segment as a
 * tessellated capsule, an unbounded plane as the polygon where it cuts the
 * range's box (for the sphere ranges, the box around the final sphere). Every
 * cell of an object carries: "Rank" (its place in the result, from 0),
 * "ObjectKind" (0 triangle, 1 sphere or point, 2 plane, 3 tube segment),
 * "PrimitiveId" (global primitive id, in the scene's order: triangles, tube
 * segments, points, spheres; -1 for a plane),
 * "PlaneId" (-1 for a primitive), "ObjectId" (the scene's object id: the
 * input's index for a dataset), "Distance" (0 for the box query).
 * Field data: "Structure" (the walked structure's name), "ObjectsFound",
 * and the query's cost: "NodesVisited", "BoxesTested", "NodesCulled",
 * "PrimitivesTested" (as rayscope query reports them).
 *
 * Output port 1, the range itself: the box, or the sphere (for the nearest
 * query the sphere through the k-th object found: the final, shrunk range).
 *
 * A range the query refuses (non-finite numbers, a box with min > max, a
 * negative radius, NumberOfNeighbors < 1) is an error (vtkErrorMacro) with
 * empty outputs.
 */
#ifndef vtkRayScopeRangeQuery_h
#define vtkRayScopeRangeQuery_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkRayScopeSceneFilter.h"

class vtkRayScopeImageAlgorithm;

class RAYSCOPEVTK_EXPORT vtkRayScopeRangeQuery : public vtkRayScopeSceneFilter {
 public:
  static vtkRayScopeRangeQuery* New();
  vtkTypeMacro(vtkRayScopeRangeQuery, vtkRayScopeSceneFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Which range (default QUERY_BOX).
  enum QueryTypes { QUERY_BOX = 0, QUERY_SPHERE = 1, QUERY_NEAREST = 2 };
  vtkSetClampMacro(QueryType, int, QUERY_BOX, QUERY_NEAREST);
  vtkGetMacro(QueryType, int);
  void SetQueryTypeToBox() { this->SetQueryType(QUERY_BOX); }
  void SetQueryTypeToSphere() { this->SetQueryType(QUERY_SPHERE); }
  void SetQueryTypeToNearest() { this->SetQueryType(QUERY_NEAREST); }
  ///@}

  ///@{
  /// The box of QUERY_BOX: (xmin, xmax, ymin, ymax, zmin, zmax), world
  /// coordinates (default the unit cube around the origin, -0.5 .. 0.5).
  vtkSetVector6Macro(Box, double);
  vtkGetVector6Macro(Box, double);
  ///@}

  ///@{
  /// The center of QUERY_SPHERE and the point of QUERY_NEAREST (default the
  /// origin), and the sphere's radius (default 1).
  vtkSetVector3Macro(Center, double);
  vtkGetVector3Macro(Center, double);
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  ///@}

  ///@{
  /// k of QUERY_NEAREST (default 1).
  vtkSetMacro(NumberOfNeighbors, int);
  vtkGetMacro(NumberOfNeighbors, int);
  ///@}

  ///@{
  /// Theta and phi resolution of the spheres drawn (found analytic spheres
  /// and the range of port 1; default 24, at least 4).
  vtkSetClampMacro(SphereResolution, int, 4, 512);
  vtkGetMacro(SphereResolution, int);
  ///@}

 protected:
  vtkRayScopeRangeQuery();
  ~vtkRayScopeRangeQuery() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  int QueryType;
  double Box[6];
  double Center[3];
  double Radius;
  int NumberOfNeighbors;
  int SphereResolution;

 private:
  vtkRayScopeRangeQuery(const vtkRayScopeRangeQuery&) = delete;
  void operator=(const vtkRayScopeRangeQuery&) = delete;
};

#endif
