/**
 * @class   pqRayScopeRefinement
 * @brief   Renders RayScope views again while they refine (ParaView's client).
 *
 * A RayScope view with Refine Progressively on adds one sample per pixel to
 * its image at each still render while the camera rests (vtkRayScopeRenderView).
 * After every render of such a view this behavior reads its ImagePasses and,
 * while an image under way lacks passes (none after a failed render), asks for
 * another still render through the client's render scheduling
 * (pqView::render()), so the GUI stays responsive and a camera move (an
 * interactive render, which starts the image again) takes over at once. The plugin starts it with
 * ParaView's GUI; pvpython and pvbatch render the passes themselves (Render() again, or a
 * screenshot, which completes the image).
 */
#ifndef pqRayScopeRefinement_h
#define pqRayScopeRefinement_h

#include <QObject>

class pqView;

class pqRayScopeRefinement : public QObject {
  Q_OBJECT

 public:
  explicit pqRayScopeRefinement(QObject* parent = nullptr);
  ~pqRayScopeRefinement() override;

  void onStartup();
  void onShutdown();

 private Q_SLOTS:
  void watch(pqView* view);
  void renderedOne();

 private:
  Q_DISABLE_COPY(pqRayScopeRefinement)
};

#endif
