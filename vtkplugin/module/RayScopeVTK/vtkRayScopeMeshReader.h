/**
 * @class   vtkRayScopeMeshReader
 * @brief   Reads the dataset files of rayscope_vtkio::kMeshFileFormats (.obj,
 *          .stl, .ply, .vtp, .vtu, .vti, .vtk legacy, and the parallel
 *          .pvtp, .pvtu, .pvti with their pieces) with RayScope's checks
 *          before VTK's reader: the safe way to read a file you did not write.
 *          Composite files (.vtm, .vtpc, Exodus) are the rayscope command's.
 *
 * VTK's own readers trust what a file declares: a truncated ASCII PLY aborts
 * the process inside vtkPLYReader, a PLY declaring 1e8 vertices in a few
 * bytes never finishes (VTK 9.1; ParaView 5.11's aborts), a truncated or
 * over-declared binary STL gives part of its triangles without a word, and a legacy file naming
 * point 7 of 3 reaches the filters downstream. This reader is rayscope_vtkio::read_dataset_file()
 * (library rayscope_vtkio, the function the rayscope command reads mesh files
 * with): the file is checked first (mesh_checks.h: sizes and counts against
 * the bytes the file has, the header layouts VTK's readers need), then read
 * by VTK's reader of its format (chosen by the extension, in any letter
 * case), whose errors and warnings are caught, then the cells of what it read
 * are checked to name only existing points. A file that reads as a dataset
 * without points (an empty file, or a text file cut off before its first
 * point, which VTK's readers read without a word) is refused too: a dataset
 * from this reader always has points.
 *
 * Output: the dataset VTK's reader gave, as its own type (vtkPolyData for
 * .vtp, .pvtp, .stl, .ply and .obj; vtkUnstructuredGrid for .vtu and .pvtu;
 * vtkImageData for .vti and .pvti; for legacy .vtk
 * whatever the file holds: polydata, an unstructured grid, image data
 * (vtkStructuredPoints), a structured or a rectilinear grid), unchanged but
 * for one thing: a point or cell array with fewer tuples than the dataset
 * has points or cells, which VTK's filters would read past its end, is
 * removed with a warning (vtkWarningMacro) naming it. vtkOBJReader makes one
 * from a valid OBJ file whose 'vn' lines no face names (4 points, a
 * "Normals" array of 1 tuple).
 * The type is only known once the file is read, so the file is read in
 * RequestDataObject (the pipeline's first pass, run again whenever FileName
 * or Modified() changes the reader) and kept; RequestInformation announces a
 * structured dataset's extent (and an image's origin and spacing), and
 * RequestData shallow-copies the kept dataset into the output.
 *
 * A missing, unsupported or damaged file: one error (vtkErrorMacro, an
 * ErrorEvent on this reader) whose text is "FILE: problem", RequestData
 * returns 0 (so vtkExecutive::Update() returns 0), and the output is empty,
 * of the type it had (vtkPolyData when there was none). Never a crash, a
 * hang or a partial dataset: every damaged file the mesh fuzzer found
 * (tests/fuzz/regressions/mesh_loader) is refused.
 *
 * Files are read one at a time: while a file is read, VTK's global output
 * window is replaced by one that captures the reader's messages.
 */
#ifndef vtkRayScopeMeshReader_h
#define vtkRayScopeMeshReader_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkDataSetAlgorithm.h"
#include "vtkSmartPointer.h"  // Data

#include <string>  // Error

class vtkDataSet;

class RAYSCOPEVTK_EXPORT vtkRayScopeMeshReader : public vtkDataSetAlgorithm {
 public:
  static vtkRayScopeMeshReader* New();
  vtkTypeMacro(vtkRayScopeMeshReader, vtkDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  /// 1 if `name` is a regular file with an extension this reader reads
  /// (the dataset formats above, any letter case), else 0. Only the
  /// name and the kind of file are looked at, not the contents: a damaged
  /// file is accepted here and refused with an error when it is read, so
  /// that ParaView offers this reader for it and the user sees why.
  virtual int CanReadFile(const char* name);

 protected:
  vtkRayScopeMeshReader();
  ~vtkRayScopeMeshReader() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation* request, vtkInformationVector** inputVector,
                        vtkInformationVector* outputVector) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
                         vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  char* FileName;

 private:
  // Reads FileName into Data, or explains in Error why not.
  void ReadFile();

  // The dataset of the last read (null after an error), the error ("" after
  // a success) and what was removed from the dataset ("" when nothing was).
  vtkSmartPointer<vtkDataSet> Data;
  std::string Error;
  std::string Warning;

  vtkRayScopeMeshReader(const vtkRayScopeMeshReader&) = delete;
  void operator=(const vtkRayScopeMeshReader&) = delete;
};

#endif
