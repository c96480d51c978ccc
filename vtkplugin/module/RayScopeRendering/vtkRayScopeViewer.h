/**
 * @class   vtkRayScopeViewer
 * @brief   The interactive ray-tree and acceleration-structure debugger: a
 *          ray-traced image and the scene in 3D with the ray tree of a
 *          picked pixel, side by side.
 *
 * @code{.py}
 *   viewer = rayscope.vtkRayScopeViewer()
 *   viewer.SetSceneSource(tracer)   # a vtkRayScopeImageAlgorithm: scene and settings
 *   viewer.PickPixel(160, 120)      # optional; VTK image coordinates
 *   viewer.Start()                  # opens the window, renders, runs the event loop
 * @endcode
 *
 * One vtkRenderWindow with three viewports: the ray-traced image (left; its
 * ImageMode shows colors, the BVH cost heat map, normals, depth or object
 * ids), the scene drawn by VTK (right: the triangles, spheres and planes the
 * tracer intersects, in their material colors, half transparent; the camera
 * as a frustum with its image plane and the pixel grid around the picked
 * pixel; lights as spheres) and a text panel below with the picked
 * pixel's ray tree as `rayscope inspect` prints it (the selected ray marked
 * ">>", and drawn white and thick in 3D). The overlay is the output of a
 * vtkRayScopeRayTreeSource (a line per ray in its kind's color, gray for rays
 * the integrator skipped, hit points, shading normals, a red dot where a
 * shadow ray is blocked), and of a vtkRayScopeAccelSource (the structure the
 * rays walk, as the scene source's Accel chose it: the BVH, the kD-tree's,
 * grid's or octree's cells, ...; by level, or the selected ray's walk played
 * node by node: entered boxes, missed boxes, culled boxes and the hit leaf in
 * the colors of the legend, which names the structure). Below, "BVH" stands
 * for whichever structure is drawn.
 *
 * Interaction (an interactor style that extends trackball camera):
 * - a click in the image picks that pixel; a click (press and release
 *   without moving) on a surface in the 3D view picks the pixel that sees
 *   that point; dragging in the 3D view orbits;
 * - keys (the help line lists them): Up/Down grow and shrink the shown tree
 *   by one recursion depth; Right/Left select the next/previous ray in trace
 *   order (rays after it are hidden); t/T play the selected ray's BVH walk
 *   one node forward/back; b shows/hides the BVH, l/L walk its levels; k
 *   shows one ray kind only (cycles); d shows labels (ray id, depth,
 *   weight); g draws the tree as a diagram in the panel instead of its text; m cycles the image
 * mode; +/- change the samples per pixel, ]/[ the maximum depth, p switches central and parallel
 * projection, r takes the 3D view's camera, each then re-renders; f/F frame the selected ray / the
 * scene; PageDown/PageUp go to the next/previous chapter of a lecture (AddChapter()); s saves a
 *   screenshot; x exports the ray tree and the BVH as .vtp; q quits. At the end of a range a key
 * does nothing and says so in the message line.
 *
 * Renders run on a worker thread (the core's frame loop, tile by tile); a
 * repeating timer on the interactor shows finished tiles and the progress
 * while the window stays responsive. WaitForRender() finishes a render
 * without an event loop (scripts, tests). Picking during a render waits for
 * it (the tree is a replay of one pixel of the same scene).
 *
 * Pixels are VTK image coordinates: (0, 0) is the bottom-left pixel, unlike
 * the rayscope command's --pixel, whose (0, 0) is the top-left pixel.
 */
#ifndef vtkRayScopeViewer_h
#define vtkRayScopeViewer_h

#include "RayScopeRenderingModule.h"  // export macro
#include "vtkObject.h"

#include <string>  // std::string

class vtkImageData;
class vtkPolyData;
class vtkRayScopeAccelSource;
class vtkRayScopeImageAlgorithm;
class vtkRayScopeRayTreeSource;
class vtkRenderWindow;
class vtkRenderWindowInteractor;
class vtkRenderer;

class RAYSCOPERENDERING_EXPORT vtkRayScopeViewer : public vtkObject {
 public:
  static vtkRayScopeViewer* New();
  vtkTypeMacro(vtkRayScopeViewer, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The image algorithm holding the scene and the render settings (size,
  /// samples, depth, cutoff, threads, accel). Never null: a new viewer has
  /// its own, without a scene.
  void SetSceneSource(vtkRayScopeImageAlgorithm* source);
  vtkRayScopeImageAlgorithm* GetSceneSource();
  ///@}

  /// The window, its interactor and the three renderers (made on first use).
  vtkRenderWindow* GetRenderWindow();
  vtkRenderWindowInteractor* GetInteractor();
  vtkRenderer* GetImageRenderer();
  vtkRenderer* GetSceneRenderer();
  vtkRenderer* GetTextRenderer();

  /// Builds the window and starts the first render (returns 0, with the
  /// error in GetMessage() and a vtkErrorMacro, when the scene cannot be
  /// rendered). Start() calls it.
  int Initialize();
  /// Initialize(), then the interactor's event loop.
  void Start();

  /// Starts a render with the current settings on the worker thread
  /// (finishing a running one first); the window shows its tiles as they
  /// come (the event loop's timer) or all of it after WaitForRender().
  /// Returns 0 when the settings or the scene are invalid.
  int Rerender();
  /// Waits for the running render and shows it; returns 1 when an image is
  /// shown.
  int WaitForRender();
  /// A render is running.
  bool IsRendering();
  /// Seconds from the start of the last render to its last tile.
  vtkGetMacro(LastRenderSeconds, double);

  ///@{
  /// Picks pixel (i, j) (VTK image coordinates) and shows its ray tree;
  /// returns 0 (and changes nothing) for a pixel outside the image.
  int PickPixel(int i, int j);
  /// Picks the pixel under display position (x, y): in the image viewport
  /// that pixel, in the 3D view the pixel that sees the surface point there.
  /// Returns 0 when there is nothing to pick.
  int PickAtDisplay(int x, int y);
  /// The picked pixel (-1, -1 before a pick).
  vtkGetVector2Macro(PickedPixel, int);
  ///@}

  /// Points the 3D view's camera from `eye` at `at` (world coordinates),
  /// with the scene camera's up direction as far as it is not along the
  /// view: what `rayscope view --view-camera` sets. Returns 0 and changes
  /// nothing before Initialize(), for points that are not finite, or for
  /// the same point twice.
  int SetSceneView(const double eye[3], const double at[3]);

  /// Whether HandleKey() has an action for `keysym` (so that scripted keys,
  /// such as a lecture's chapters' or `rayscope view --keys`, are checked
  /// before a window opens).
  static bool IsKey(const char* keysym);
  /// Handles a key as the window does (keysym as VTK names it: "Up", "plus",
  /// "t", ...); returns 0 for a key the viewer does not use.
  int HandleKey(const char* keysym);

  ///@{
  /// What is shown of the tree: rays up to recursion depth ShownDepth, up to
  /// ray SelectedRay in trace order (-1: all, nothing selected), of kind
  /// ShownKind only (-1: all kinds; else a rayscope::RayKind value).
  vtkGetMacro(ShownDepth, int);
  vtkGetMacro(SelectedRay, int);
  vtkGetMacro(ShownKind, int);
  /// Nodes of the selected ray's walk shown (-1: the walk is not played).
  vtkGetMacro(TraversalSteps, int);
  vtkGetMacro(ShowBVH, bool);
  vtkGetMacro(BVHLevel, int);
  /// Labels "#id dDEPTH wWEIGHT" on the shown rays (key d).
  vtkGetMacro(ShowLabels, bool);
  /// The panel shows the tree diagram instead of the text (key g).
  vtkGetMacro(ShowTreeDiagram, bool);
  /// The panel shows the packet the picked pixel's primary ray was traced in
  /// (key c; rayscope::format_packet_text()) instead of the tree's text, and
  /// the image outlines the packet's block of pixels.
  vtkGetMacro(ShowPacket, bool);
  ///@}

  /// Image modes (the values of the image viewport's ImageMode).
  enum ImageModes { COLOR = 0, COST = 1, NORMALS = 2, DEPTH = 3, OBJECT_IDS = 4 };
  void SetImageMode(int mode);
  vtkGetMacro(ImageMode, int);

  /// The image shown (RGB bytes of the ImageMode; while a render runs, its
  /// finished tiles) and the last finished render with all its arrays (as
  /// vtkRayScopeImageAlgorithm outputs them; empty before the first). The
  /// viewer keeps two sets of image arrays and renders into the older one:
  /// an array of the last image is overwritten by the render after next
  /// (DeepCopy() the image to keep it longer).
  vtkImageData* GetShownImage();
  vtkImageData* GetLastImage();

  /// The rays shown in the 3D view (the filtered ray-tree polydata: line
  /// cells for rays, vertex cells for hit points, the source's cell data
  /// except the strings of "KindName", which "Kind" numbers).
  vtkPolyData* GetShownRays();
  /// The ray labels (a vertex per shown ray at its middle; point data
  /// "Label"), drawn when ShowLabels is on.
  vtkPolyData* GetRayLabels();
  /// The markers of blocked shadow rays: a vertex where each shown shadow
  /// ray meets its nearest occluder.
  vtkPolyData* GetOccluderMarkers();
  /// The picked pixel's marker in the image viewport (pixel coordinates): a
  /// square around the pixel, four arms, and with ShowPacket the outline of
  /// the packet's block of pixels (the last cell).
  vtkPolyData* GetPixelMarker();
  /// The box of each node the picked pixel's packet entered (ShowPacket;
  /// empty otherwise), in walk order: 12 line cells per box, cell data
  /// "ActiveRays" (the rays active in the node, 1 to 16, its color) and
  /// "Step" (1: the root).
  vtkPolyData* GetPacketBoxes();
  /// The tree diagram (key g; empty when not shown): a vertex per ray and a
  /// line from each ray's parent to it, in pixels of the panel's viewport,
  /// each ray below its parent and leaves in trace order from left to right;
  /// cell data "Colors" (RGB bytes: the kind's color, dimmed for a ray the
  /// 3D view hides, white for the selected ray) and "RayId".
  vtkPolyData* GetTreeDiagram();
  /// The BVH boxes shown (empty when hidden).
  vtkPolyData* GetShownBVH();
  /// While a walk is played: the step numbers of the nodes entered (a vertex
  /// at each box's top left corner, point data "Step": "1", or "2, 3" for
  /// nested boxes sharing that corner), and the node entered last (its
  /// box's cells, drawn thick in its state's color). Empty otherwise.
  vtkPolyData* GetWalkSteps();
  vtkPolyData* GetWalkCurrentNode();
  /// The sources behind the overlay.
  vtkRayScopeRayTreeSource* GetRayTreeSource();
  vtkRayScopeAccelSource* GetAccelSource();
  /// Deprecated name of GetAccelSource() (warns; removed in the next release).
  vtkRayScopeAccelSource* GetBVHSource();

  /// The picked pixel's tree as `rayscope inspect` prints it (empty before a
  /// pick), and the text panel as shown.
  const char* GetInspectText();
  const char* GetPanelText();
  /// The message line (errors, the end of a key's range, render progress).
  const char* GetMessage();
  /// The help line.
  static const char* GetHelpText();

  ///@{
  /// Writes the window as PNG (returns 0 on failure, with a message).
  int SaveScreenshot(const char* filename);
  /// Writes the shown ray tree to PREFIX_raytree.vtp and the BVH (every
  /// node, or the played walk) to PREFIX_bvh.vtp.
  int ExportVTP(const char* prefix);
  /// Where the s and x keys write: PREFIX_N.png, PREFIX_N_raytree.vtp, ...
  /// (default "rayscope_view").
  vtkSetStringMacro(OutputPrefix);
  vtkGetStringMacro(OutputPrefix);
  ///@}

  ///@{
  /// A lecture: chapters shown one at a time, PageDown / PageUp (keysyms
  /// "Next", "Prior") going to the next / previous one. A chapter is a scene
  /// source (its scene and render settings), a title, a one-line caption of
  /// what to look at (drawn on top of the 3D view, with the chapter's number
  /// and title), a pixel picked on entering it (VTK image coordinates; -1, -1:
  /// none) and the keys then pressed (comma-separated, as HandleKey() names
  /// them; empty: none).
  void AddChapter(vtkRayScopeImageAlgorithm* source, const char* title, const char* caption,
                  int pickI, int pickJ, const char* keys);
  int GetNumberOfChapters();
  /// Shows chapter n (from 0): its scene, framed in the 3D view and rendered,
  /// the other settings of the view as a new viewer has them, then its pixel
  /// picked and its keys pressed. Returns 0 and changes nothing for n outside
  /// the chapters; returns 0 with the error in GetMessage() when the
  /// chapter's scene cannot be rendered or a key is not the viewer's.
  int SetChapter(int n);
  /// The chapter shown (-1: none).
  vtkGetMacro(Chapter, int);
  /// The caption line on top of the 3D view ("3/16 Shadow rays: ..."; empty
  /// without chapters).
  const char* GetCaption();
  ///@}

  /// Window size in pixels (default 1400 x 820; set before Initialize()).
  vtkSetVector2Macro(WindowSize, int);
  vtkGetVector2Macro(WindowSize, int);
  /// The smallest window that still shows every part.
  static constexpr int MinWindowWidth = 640, MinWindowHeight = 400;

  /// Scale of every text of the window (the help and message lines, the
  /// panel, the ray labels, the legend's box): 1 by default, 2 for a lecture
  /// hall; at most MaxFontScale. Set before Initialize().
  vtkSetMacro(FontScale, double);
  vtkGetMacro(FontScale, double);
  static constexpr double MinFontScale = 0.5, MaxFontScale = 4.0;

  /// Why WindowSize and FontScale cannot be used, in one line, or empty: the
  /// one check of both (Initialize() fails with it; `rayscope view` prints it).
  std::string SettingsError() const;

 protected:
  vtkRayScopeViewer();
  ~vtkRayScopeViewer() override;

  int PickedPixel[2];
  int ShownDepth;
  int SelectedRay;
  int ShownKind;
  int TraversalSteps;
  bool ShowBVH;
  int BVHLevel;
  int ImageMode;
  bool ShowLabels;
  bool ShowTreeDiagram;
  bool ShowPacket;
  double LastRenderSeconds;
  char* OutputPrefix;
  int WindowSize[2];
  double FontScale;
  int Chapter;

 private:
  vtkRayScopeViewer(const vtkRayScopeViewer&) = delete;
  void operator=(const vtkRayScopeViewer&) = delete;

  struct Internals;
  Internals* Internal;
  friend struct Internals;
};

#endif
