#include "pqRayScopeRefinement.h"

#include "pqApplicationCore.h"
#include "pqServerManagerModel.h"
#include "pqView.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"

#include <QTimer>

namespace {
// The proxy name of the view this behavior watches (RayScope.xml).
constexpr const char* kRayScopeView = "RayScopeView";
}  // namespace

pqRayScopeRefinement::pqRayScopeRefinement(QObject* parent) : QObject(parent) {}

pqRayScopeRefinement::~pqRayScopeRefinement() = default;

void pqRayScopeRefinement::onStartup() {
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  QObject::connect(model, &pqServerManagerModel::viewAdded, this, &pqRayScopeRefinement::watch);
  for (pqView* view : model->findItems<pqView*>()) this->watch(view);
}

void pqRayScopeRefinement::onShutdown() {}

void pqRayScopeRefinement::watch(pqView* view) {
  if (!view || !view->getProxy() || view->getProxy()->GetXMLName() != std::string(kRayScopeView))
    return;
  QObject::connect(view, &pqView::endRender, this, &pqRayScopeRefinement::renderedOne,
                   Qt::UniqueConnection);
}

void pqRayScopeRefinement::renderedOne() {
  auto* view = qobject_cast<pqView*>(this->sender());
  if (!view) return;
  vtkSMProxy* proxy = view->getProxy();
  proxy->UpdatePropertyInformation(proxy->GetProperty("ImagePasses"));
  vtkSMPropertyHelper passes(proxy, "ImagePasses");
  // Only an image under way: a failed render leaves none (0 passes), and
  // rendering it again would fail again.
  const int done = passes.GetAsInt(0), total = passes.GetAsInt(1);
  if (done < 1 || done >= total) return;
  // After the events already queued (a mouse press starts an interactive
  // render instead).
  QTimer::singleShot(0, view, [view] { view->render(); });
}
