// The datasets a VTK data object holds: itself when it is a vtkDataSet, or the
// leaves of a composite dataset (vtkMultiBlockDataSet, vtkPartitionedDataSet,
// vtkMultiPieceDataSet, vtkPartitionedDataSetCollection, nested in any way),
// each with its flat index and its name, and with the visibility, color and
// opacity a composite mapper's vtkCompositeDataDisplayAttributes gives it.
// Every RayScope front end that takes VTK data (the module's algorithms, the
// render pass through them, the rayscope command's composite files) makes one
// scene object of each leaf this returns, so blocks shadow and reflect each
// other.
#pragma once

#include <string>
#include <vector>

class vtkCompositeDataDisplayAttributes;
class vtkDataObject;
class vtkDataSet;

namespace rayscope_vtkio {

/// One dataset of a data object.
struct DatasetLeaf {
  vtkDataSet* data = nullptr;
  /// The flat index of the leaf in its composite dataset, as
  /// vtkDataObjectTreeIterator::GetCurrentFlatIndex() numbers it (pre-order,
  /// the root 0, empty blocks counted); 0 for a dataset given alone.
  unsigned flat_index = 0;
  /// The vtkCompositeDataSet::NAME() of the leaf or of its nearest named
  /// ancestor; empty when none is named.
  std::string name;
  /// A color (RGB, 0..1) and opacity the display attributes set for the leaf
  /// or an ancestor (the nearest one wins), as the composite mapper uses them.
  bool has_color = false;
  double color[3] = {1.0, 1.0, 1.0};
  bool has_opacity = false;
  double opacity = 1.0;
};

/// What dataset_leaves() found.
struct DatasetLeaves {
  /// The visible leaves that are datasets, in flat-index order.
  std::vector<DatasetLeaf> leaves;
  /// Leaves that are not datasets (e.g. a vtkTable block), one description
  /// each ("block 3 (vtkTable)"): not drawn, for the caller to report.
  std::vector<std::string> skipped;
};

/// The leaves of `data` (null gives none). Blocks that `attributes` (may be
/// null) hides, directly or through an ancestor, are left out; so are empty
/// (null) blocks.
DatasetLeaves dataset_leaves(vtkDataObject* data,
                             vtkCompositeDataDisplayAttributes* attributes = nullptr);

/// The datasets of dataset_leaves(data).leaves, for the functions that take
/// datasets (finite_bounds(), local_origin()).
std::vector<vtkDataSet*> leaf_datasets(const std::vector<DatasetLeaf>& leaves);

}  // namespace rayscope_vtkio
