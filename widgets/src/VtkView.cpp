#include "lodforge/widgets/VtkView.h"

#include "MeshActorBuilder.h"

#include "lodforge/render/surface.h"

#include "lodforge/metrics/heatmap.h"

#include <vtkActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCellArray.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellPicker.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGenericRenderWindowInteractor.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkOpenGLState.h>
#include <vtkPlane.h>
#include <vtkPlaneCollection.h>
#include <vtkPoints.h>
#include <vtkPointData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataSilhouette.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkTextProperty.h>
#include <vtkTexture.h>
#include <vtkUnsignedCharArray.h>

#include <QMouseEvent>
#include <QOpenGLContext>
#include <QTimer>
#include <QSurfaceFormat>
#include <QWheelEvent>
#include <qopengl.h>  // GL enums; VTK's own GL loader (glew) must not be included after it

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace lodforge::widgets {

namespace {

const char* const normalColorsName = "NormalColors";

// A checker on the texture coordinates: `cells` x `cells` squares per UV unit, the dark ones tinted red
// along u and blue along v, so both the scale and the orientation of the UV layout show. At least 16
// texels a square, so the squares stay sharp at any density.
vtkSmartPointer<vtkImageData> makeCheckerImage(int cells) {
    cells = std::clamp(cells, minUvCheckerCells, maxUvCheckerCells);
    const int cell = std::max(16, 512 / cells), size = cell * cells;
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(size, size, 1);
    image->AllocateScalars(VTK_UNSIGNED_CHAR, 4);
    auto* out = static_cast<unsigned char*>(image->GetScalarPointer());
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            unsigned char* p = out + 4 * (y * size + x);
            const bool dark = ((x / cell) + (y / cell)) % 2 == 0;
            if (dark) {
                p[0] = static_cast<unsigned char>(40 + 200 * x / size);
                p[1] = 40;
                p[2] = static_cast<unsigned char>(40 + 200 * y / size);
            } else {
                p[0] = p[1] = p[2] = 235;
            }
            p[3] = 255;
        }
    }
    return image;
}

// Normals (x, y, z) in [-1, 1] -> RGB in [0, 255], added to the part's point data once.
void ensureNormalColors(vtkPolyData* polyData) {
    vtkPointData* pd = polyData->GetPointData();
    if (pd->GetArray(normalColorsName) || !pd->GetNormals()) return;
    vtkDataArray* normals = pd->GetNormals();
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName(normalColorsName);
    colors->SetNumberOfComponents(3);
    colors->SetNumberOfTuples(normals->GetNumberOfTuples());
    for (vtkIdType i = 0; i < normals->GetNumberOfTuples(); ++i) {
        double n[3];
        normals->GetTuple(i, n);
        for (int c = 0; c < 3; ++c)
            colors->SetValue(3 * i + c, static_cast<unsigned char>(std::lround(std::clamp(n[c] * 0.5 + 0.5, 0.0, 1.0) * 255.0)));
    }
    pd->AddArray(colors);
}

}  // namespace

struct VtkView::Private {
    explicit Private(VtkView* view) : q(view) {}

    struct Actor : render::SurfaceActor {
        bool hasScalars = false;
    };

    std::vector<Actor> makeActors(const MeshScene& scene);
    void applyOptions(std::vector<Actor>& list, vtkPlane* clip);
    void updateLookupTable();

    // Observer of the render window: VTK asks us to make the context current, whether it is current,
    // and tells us when a frame is done.
    static void onWindowEvent(vtkObject*, unsigned long event, void* clientData, void* callData) {
        auto* self = static_cast<Private*>(clientData);
        QOpenGLContext* context = self->q->context();
        switch (event) {
        case vtkCommand::WindowMakeCurrentEvent:
            // Not QOpenGLWidget::makeCurrent(): that also rebinds Qt's framebuffer behind VTK's state cache
            // while VTK sets up its own framebuffers, and the picture comes out black.
            if (context && self->surface) context->makeCurrent(self->surface);
            break;
        case vtkCommand::WindowIsCurrentEvent:
            *static_cast<bool*>(callData) = context && QOpenGLContext::currentContext() == context;
            break;
        case vtkCommand::WindowFrameEvent:
            // A frame rendered outside paintGL (nothing of ours does that) still has to reach the screen.
            if (!self->inPaint) self->q->update();
            break;
        default:
            break;
        }
    }

    // The interactor never renders itself (EnableRenderOff); it asks for a repaint instead.
    static void onInteractorRender(vtkObject*, unsigned long, void* clientData, void*) {
        VtkView* view = static_cast<Private*>(clientData)->q;
        view->update();
        emit view->cameraChanged();
    }

    VtkView* q;
    vtkNew<vtkGenericOpenGLRenderWindow> window;
    vtkNew<vtkRenderer> renderer;
    vtkNew<vtkGenericRenderWindowInteractor> interactor;
    vtkNew<vtkInteractorStyleTrackballCamera> style;
    vtkNew<vtkCallbackCommand> windowObserver;
    vtkNew<vtkCallbackCommand> renderObserver;

    QSurface* surface = nullptr;
    QMetaObject::Connection contextDestroyed;
    bool inPaint = false;
    quint64 frames = 0;

    std::shared_ptr<const MeshScene> scene;
    std::vector<Actor> actors;
    ViewOptions options;

    std::shared_ptr<const MeshScene> compareScene;
    std::vector<Actor> compareActors;
    double split = 0.5;
    vtkNew<vtkPlane> keepRight;  // the scene's half
    vtkNew<vtkPlane> keepLeft;   // the compare scene's half

    std::shared_ptr<const MeshScene> overlayScene;
    vtkSmartPointer<vtkActor> overlayActor;
    vtkSmartPointer<vtkPolyDataMapper> overlayMapper;
    void applyOverlayOptions();
    void placeScalarBar(int width, int height);

    std::shared_ptr<const MeshScene> outlineScene;
    std::vector<vtkSmartPointer<vtkActor>> outlineActors;
    std::vector<vtkSmartPointer<vtkPolyDataSilhouette>> silhouettes;  // follow the active camera

    vtkSmartPointer<vtkActor> markerActor;
    std::vector<vtkSmartPointer<vtkBillboardTextActor3D>> markerLabels;

    vtkSmartPointer<vtkCamera> ownCamera;
    vtkSmartPointer<vtkTexture> checker;
    int checkerCells = ViewOptions{}.uvCheckerCells;  // the checker image's density
    vtkNew<vtkLookupTable> lut;
    vtkNew<vtkScalarBarActor> scalarBar;
    bool scalarBarVisible = true;
    double scalarRange = 0;
    vtkNew<vtkCellPicker> picker;
    QTimer hoverTimer;
    QPoint hoverPosition;
    std::optional<QPointF> pressPosition;  // of a left press, for clicked()
};

std::vector<VtkView::Private::Actor> VtkView::Private::makeActors(const MeshScene& meshScene) {
    std::vector<Actor> list;
    for (const MeshScene::Part& part : meshScene.parts) {
        Actor a;
        static_cast<render::SurfaceActor&>(a) = render::makeSurfaceActor(part);
        a.hasScalars = meshScene.hasScalars && part.polyData->GetPointData()->GetArray(scalarArrayName()) != nullptr;
        renderer->AddActor(a.actor);
        list.push_back(std::move(a));
    }
    return list;
}

void VtkView::Private::updateLookupTable() {
    double top = scalarRange > 0 ? scalarRange : 0.0;
    if (!(top > 0)) {
        if (scene && scene->hasScalars) top = scene->scalarMax;
    }
    if (!(top > 0)) top = 1e-9;  // an all-zero field maps to the bottom of the colour map
    lut->SetRange(0.0, top);
    lut->Build();
    const bool heat = scene && scene->hasScalars;
    scalarBar->SetVisibility(heat && scalarBarVisible);
}

VtkView::VtkView(QWidget* parent) : QOpenGLWidget(parent), d(std::make_unique<Private>(this)) {
    setFocusPolicy(Qt::StrongFocus);

    const QColor background = viewBackgroundColor();
    d->renderer->SetBackground(background.redF(), background.greenF(), background.blueF());
    d->renderer->SetTwoSidedLighting(true);
    d->window->AddRenderer(d->renderer);
    // No GL context until initializeGL; VTK must not try to render before.
    d->window->SetReadyForRendering(false);
    d->window->SetFrameBlitModeToNoBlit();
    d->window->SetMultiSamples(0);

    d->windowObserver->SetClientData(d.get());
    d->windowObserver->SetCallback(&Private::onWindowEvent);
    d->window->AddObserver(vtkCommand::WindowMakeCurrentEvent, d->windowObserver);
    d->window->AddObserver(vtkCommand::WindowIsCurrentEvent, d->windowObserver);
    d->window->AddObserver(vtkCommand::WindowFrameEvent, d->windowObserver);

    d->interactor->SetRenderWindow(d->window);
    d->interactor->SetInteractorStyle(d->style);
    d->interactor->EnableRenderOff();
    d->renderObserver->SetClientData(d.get());
    d->renderObserver->SetCallback(&Private::onInteractorRender);
    d->interactor->AddObserver(vtkCommand::RenderEvent, d->renderObserver);
    d->interactor->Initialize();

    d->ownCamera = d->renderer->GetActiveCamera();

    // Viridis, the colour map of lodforge::make_heatmap, so studio and exported heat maps agree.
    d->lut->SetNumberOfTableValues(256);
    for (int i = 0; i < 256; ++i) {
        const Vec4f c = lodforge::viridis(static_cast<float>(i) / 255.f);
        d->lut->SetTableValue(i, c.x, c.y, c.z, 1.0);
    }
    d->lut->SetRange(0.0, 1.0);
    d->scalarBar->SetLookupTable(d->lut);
    d->scalarBar->SetTitle("Error");
    d->scalarBar->SetNumberOfLabels(5);
    d->scalarBar->SetLabelFormat("%.3g");
    d->scalarBar->SetPosition(0.86, 0.08);
    d->scalarBar->SetWidth(0.12);
    d->scalarBar->SetHeight(0.8);
    d->scalarBar->SetMaximumWidthInPixels(110);
    d->scalarBar->UnconstrainedFontSizeOn();  // fixed sizes instead of text scaled to the bar
    d->scalarBar->GetLabelTextProperty()->SetFontSize(12);
    d->scalarBar->GetTitleTextProperty()->SetFontSize(13);
    d->scalarBar->SetVisibility(false);
    d->renderer->AddActor2D(d->scalarBar);

    auto checker = vtkSmartPointer<vtkTexture>::New();
    checker->SetInputData(makeCheckerImage(d->checkerCells));
    checker->InterpolateOn();
    checker->RepeatOn();
    checker->SetColorModeToDirectScalars();
    d->checker = checker;

    d->picker->SetTolerance(0.0005);
    d->picker->PickFromListOn();
    d->hoverTimer.setSingleShot(true);
    d->hoverTimer.setInterval(30);
    connect(&d->hoverTimer, &QTimer::timeout, this, &VtkView::pickHover);
    setMouseTracking(true);
}

void VtkView::setDefaultSurfaceFormat() {
    QSurfaceFormat format;
    format.setRenderableType(QSurfaceFormat::OpenGL);
    format.setVersion(3, 2);
    format.setProfile(QSurfaceFormat::CoreProfile);
    format.setDepthBufferSize(24);
    format.setStencilBufferSize(8);
    format.setSamples(0);
    QSurfaceFormat::setDefaultFormat(format);
}

VtkView::~VtkView() {
    disconnect(d->contextDestroyed);
    if (context()) {
        makeCurrent();
        releaseGraphics();
        doneCurrent();
    }
    d->interactor->RemoveObserver(d->renderObserver);
    d->window->RemoveObserver(d->windowObserver);
}

void VtkView::releaseGraphics() {
    if (!d->window->GetReadyForRendering()) return;
    // Called with the context current (aboutToBeDestroyed, destructor): VTK frees its GL objects.
    d->window->Finalize();
    d->window->SetReadyForRendering(false);
}

void VtkView::initializeGL() {
    QOpenGLContext* ctx = context();
    d->surface = ctx->surface();
    // The context is recreated when the widget moves to another window (e.g. a floating dock): release
    // VTK's resources while the old one is still alive.
    disconnect(d->contextDestroyed);
    d->contextDestroyed = connect(ctx, &QOpenGLContext::aboutToBeDestroyed, this, [this] {
        makeCurrent();
        releaseGraphics();
    }, Qt::DirectConnection);

    d->window->SetOwnContext(false);
    d->window->SetReadyForRendering(true);
    d->window->OpenGLInitContext();
    const qreal ratio = devicePixelRatioF();
    d->interactor->UpdateSize(static_cast<int>(std::lround(width() * ratio)),
                              static_cast<int>(std::lround(height() * ratio)));
}

void VtkView::resizeGL(int w, int h) {
    const qreal ratio = devicePixelRatioF();
    const int pw = static_cast<int>(std::lround(w * ratio)), ph = static_cast<int>(std::lround(h * ratio));
    d->interactor->UpdateSize(pw, ph);
    d->placeScalarBar(pw, ph);
}

// The labels keep a fixed font size, so the bar keeps a fixed width in pixels at the right edge: as a
// fraction of the view (0.12 at 0.86) a side-by-side tile clipped its labels at the edge. Short views
// get fewer labels, so they do not overlap.
void VtkView::Private::placeScalarBar(int width, int height) {
    constexpr int barPixels = 90, marginPixels = 6;
    const double w = std::max(width, 1);
    const double fraction = std::min(0.45, barPixels / w);
    scalarBar->SetWidth(fraction);
    scalarBar->SetPosition(std::max(0.0, 1.0 - fraction - marginPixels / w), 0.08);
    scalarBar->SetMaximumWidthInPixels(barPixels);
    scalarBar->SetNumberOfLabels(height < 160 ? 2 : height < 260 ? 3 : 5);
}

void VtkView::paintGL() {
    if (!d->window->GetReadyForRendering()) return;
    d->inPaint = true;
    vtkOpenGLState* state = d->window->GetState();
    // Qt changed GL state behind VTK's cache: re-read it, and restore it for Qt afterwards.
    state->Reset();
    state->Push();
    state->vtkglDepthFunc(GL_LEQUAL);  // Qt leaves GL_LESS; VTK's passes expect LEQUAL

    // The camera may be shared with views of other bounds: fit the clipping range to this one's.
    d->renderer->ResetCameraClippingRange();
    if (!d->compareActors.empty()) updateSplitPlanes();
    d->window->Render();

    const int w = d->window->GetSize()[0];
    const int h = d->window->GetSize()[1];
    state->vtkglBindFramebuffer(GL_DRAW_FRAMEBUFFER, defaultFramebufferObject());
    d->window->BlitDisplayFramebuffer(0, 0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    // VTK leaves alpha at 0; Qt composes (and grabFramebuffer reads) with alpha, so make it opaque.
    state->vtkglViewport(0, 0, w, h);
    state->vtkglDisable(GL_SCISSOR_TEST);
    state->vtkglColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
    state->vtkglClearColor(0.f, 0.f, 0.f, 1.f);
    state->vtkglClear(GL_COLOR_BUFFER_BIT);
    state->vtkglColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);

    state->Pop();
    d->inPaint = false;
    ++d->frames;
    emit frameRendered();
}

void VtkView::setScene(std::shared_ptr<const MeshScene> scene, bool resetCamera) {
    for (const Private::Actor& a : d->actors) d->renderer->RemoveActor(a.actor);
    d->actors.clear();
    d->picker->InitializePickList();
    d->picker->RemoveAllLocators();
    d->scene = std::move(scene);
    if (d->scene) {
        d->actors = d->makeActors(*d->scene);
        for (const MeshScene::Part& part : d->scene->parts)
            if (part.locator) d->picker->AddLocator(part.locator);
    }
    for (const Private::Actor& a : d->actors) d->picker->AddPickList(a.actor);
    d->updateLookupTable();
    applyViewOptions();
    if (resetCamera) resetView();
    update();
}

void VtkView::setCompareScene(std::shared_ptr<const MeshScene> reference) {
    for (const Private::Actor& a : d->compareActors) d->renderer->RemoveActor(a.actor);
    d->compareActors.clear();
    d->compareScene = std::move(reference);
    if (d->compareScene) d->compareActors = d->makeActors(*d->compareScene);
    applyViewOptions();
    update();
}

const std::shared_ptr<const MeshScene>& VtkView::compareScene() const { return d->compareScene; }

void VtkView::setSplitPosition(double fraction) {
    const double f = std::clamp(std::isfinite(fraction) ? fraction : 0.5, 0.0, 1.0);
    if (f == d->split) return;
    d->split = f;
    update();
}

double VtkView::splitPosition() const { return d->split; }

void VtkView::updateSplitPlanes() {
    vtkRenderer* r = d->renderer;
    const int w = d->window->GetSize()[0], h = d->window->GetSize()[1];
    if (w <= 1 || h <= 1) return;
    auto world = [r](double x, double y, double z) {
        r->SetDisplayPoint(x, y, z);
        r->DisplayToWorld();
        const double* p = r->GetWorldPoint();
        const double wc = p[3] != 0.0 ? p[3] : 1.0;
        return std::array<double, 3>{p[0] / wc, p[1] / wc, p[2] / wc};
    };
    // The plane through the eye and the screen's vertical line at the split: it divides the picture
    // exactly at that column, in perspective too.
    const double x = d->split * w;
    const auto p0 = world(x, h * 0.5, 0.0), p1 = world(x, h * 0.5, 1.0), up = world(x, h * 0.75, 0.0),
               right = world(x + 1.0, h * 0.5, 0.0);
    const std::array<double, 3> ray{p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const std::array<double, 3> vertical{up[0] - p0[0], up[1] - p0[1], up[2] - p0[2]};
    std::array<double, 3> n{ray[1] * vertical[2] - ray[2] * vertical[1], ray[2] * vertical[0] - ray[0] * vertical[2],
                            ray[0] * vertical[1] - ray[1] * vertical[0]};
    const double side = n[0] * (right[0] - p0[0]) + n[1] * (right[1] - p0[1]) + n[2] * (right[2] - p0[2]);
    if (side < 0) n = {-n[0], -n[1], -n[2]};
    d->keepRight->SetOrigin(p0.data());
    d->keepRight->SetNormal(n.data());
    d->keepLeft->SetOrigin(p0.data());
    d->keepLeft->SetNormal(-n[0], -n[1], -n[2]);
}

void VtkView::setSharedCamera(VtkView* source) {
    vtkCamera* camera = source ? source->d->renderer->GetActiveCamera() : d->ownCamera.Get();
    d->renderer->SetActiveCamera(camera);
    for (const auto& s : d->silhouettes) s->SetCamera(camera);
    update();
}

void VtkView::setOutlineScene(std::shared_ptr<const MeshScene> outline) {
    if (outline == d->outlineScene) return;
    for (const auto& actor : d->outlineActors) d->renderer->RemoveActor(actor);
    d->outlineActors.clear();
    d->silhouettes.clear();
    d->outlineScene = std::move(outline);
    if (d->outlineScene) {
        for (const MeshScene::Part& part : d->outlineScene->parts) {
            auto silhouette = vtkSmartPointer<vtkPolyDataSilhouette>::New();
            silhouette->SetInputData(part.polyData);
            silhouette->SetCamera(d->renderer->GetActiveCamera());
            silhouette->SetEnableFeatureAngle(0);  // the outline only, not the creases
            silhouette->BorderEdgesOn();           // open scans end at their border
            auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
            mapper->SetInputConnection(silhouette->GetOutputPort());
            mapper->ScalarVisibilityOff();
            // Lines pulled towards the camera, so the outline stays visible where the surfaces coincide.
            mapper->SetRelativeCoincidentTopologyLineOffsetParameters(0, -66000);
            auto actor = vtkSmartPointer<vtkActor>::New();
            actor->SetMapper(mapper);
            actor->PickableOff();
            vtkProperty* property = actor->GetProperty();
            property->SetLighting(false);
            property->SetColor(1.0, 1.0, 1.0);
            property->SetLineWidth(2.0f);
            d->renderer->AddActor(actor);
            d->outlineActors.push_back(actor);
            d->silhouettes.push_back(silhouette);
        }
    }
    update();
}

const std::shared_ptr<const MeshScene>& VtkView::outlineScene() const { return d->outlineScene; }

void VtkView::setScalarRange(double maximum) {
    d->scalarRange = std::isfinite(maximum) && maximum > 0 ? maximum : 0.0;
    d->updateLookupTable();
    update();
}

double VtkView::scalarRange() const { return d->lut->GetRange()[1]; }

void VtkView::setScalarBarVisible(bool visible) {
    d->scalarBarVisible = visible;
    d->updateLookupTable();
    update();
}

std::optional<double> VtkView::scalarAt(QPoint position) {
    if (!d->scene || !d->scene->hasScalars || !d->window->GetReadyForRendering()) return std::nullopt;
    const qreal ratio = devicePixelRatioF();
    const double x = position.x() * ratio;
    const double y = d->window->GetSize()[1] - 1 - position.y() * ratio;
    if (!d->picker->Pick(x, y, 0.0, d->renderer) || d->picker->GetCellId() < 0) return std::nullopt;
    auto* polyData = vtkPolyData::SafeDownCast(d->picker->GetDataSet());
    if (!polyData) return std::nullopt;
    vtkDataArray* values = polyData->GetPointData()->GetArray(scalarArrayName());
    if (!values) return std::nullopt;
    vtkIdType count = 0;
    const vtkIdType* ids = nullptr;
    polyData->GetCellPoints(d->picker->GetCellId(), count, ids);
    if (count != 3) return std::nullopt;
    // A triangle's parametric coordinates (r, s) weigh its corners 1 - r - s, r, s.
    const double* pc = d->picker->GetPCoords();
    const double weights[3] = {1.0 - pc[0] - pc[1], pc[0], pc[1]};
    double value = 0;
    for (int k = 0; k < 3; ++k) value += weights[k] * values->GetTuple1(ids[k]);
    return std::max(0.0, value);
}

std::optional<std::array<double, 3>> VtkView::surfacePointAt(QPoint position) {
    if (!d->scene || !d->window->GetReadyForRendering()) return std::nullopt;
    const qreal ratio = devicePixelRatioF();
    const double x = position.x() * ratio;
    const double y = d->window->GetSize()[1] - 1 - position.y() * ratio;
    if (!d->picker->Pick(x, y, 0.0, d->renderer) || d->picker->GetCellId() < 0) return std::nullopt;
    const double* p = d->picker->GetPickPosition();
    return std::array<double, 3>{p[0], p[1], p[2]};
}

VtkView::ViewCamera VtkView::viewCamera() const {
    vtkCamera* camera = d->renderer->GetActiveCamera();
    ViewCamera out;
    camera->GetPosition(out.position.data());
    camera->GetFocalPoint(out.focalPoint.data());
    camera->GetViewUp(out.viewUp.data());
    out.viewAngle = camera->GetViewAngle();
    return out;
}

void VtkView::setViewCamera(const ViewCamera& c) {
    vtkCamera* camera = d->renderer->GetActiveCamera();
    camera->SetPosition(c.position.data());
    camera->SetFocalPoint(c.focalPoint.data());
    camera->SetViewUp(c.viewUp.data());
    camera->SetViewAngle(c.viewAngle);
    camera->OrthogonalizeViewUp();
    d->renderer->ResetCameraClippingRange();
    update();
    emit cameraChanged();
}

void VtkView::setMarkers(const std::vector<ViewMarker>& markers) {
    if (d->markerActor) d->renderer->RemoveActor(d->markerActor);
    d->markerActor = nullptr;
    for (const auto& label : d->markerLabels) d->renderer->RemoveActor(label);
    d->markerLabels.clear();
    if (!markers.empty()) {
        vtkNew<vtkPoints> points;
        vtkNew<vtkCellArray> verts;
        vtkNew<vtkUnsignedCharArray> colors;
        colors->SetNumberOfComponents(3);
        for (const ViewMarker& m : markers) {
            const vtkIdType id = points->InsertNextPoint(m.position.data());
            verts->InsertNextCell(1, &id);
            const unsigned char rgb[3] = {static_cast<unsigned char>(m.color.red()),
                                          static_cast<unsigned char>(m.color.green()),
                                          static_cast<unsigned char>(m.color.blue())};
            colors->InsertNextTypedTuple(rgb);

            auto label = vtkSmartPointer<vtkBillboardTextActor3D>::New();
            label->SetInput(m.label.toUtf8().constData());
            label->SetPosition(m.position[0], m.position[1], m.position[2]);
            label->SetDisplayOffset(9, 9);
            label->PickableOff();
            vtkTextProperty* text = label->GetTextProperty();
            text->SetFontSize(16);
            text->BoldOn();
            text->ShadowOn();
            text->SetColor(m.color.redF(), m.color.greenF(), m.color.blueF());
            d->renderer->AddActor(label);
            d->markerLabels.push_back(label);
        }
        vtkNew<vtkPolyData> polyData;
        polyData->SetPoints(points);
        polyData->SetVerts(verts);
        polyData->GetPointData()->SetScalars(colors);
        vtkNew<vtkPolyDataMapper> mapper;
        mapper->SetInputData(polyData);
        mapper->SetColorModeToDirectScalars();
        d->markerActor = vtkSmartPointer<vtkActor>::New();
        d->markerActor->SetMapper(mapper);
        d->markerActor->PickableOff();
        vtkProperty* property = d->markerActor->GetProperty();
        property->SetRepresentationToPoints();
        property->RenderPointsAsSpheresOn();
        property->SetPointSize(14.f);
        d->renderer->AddActor(d->markerActor);
    }
    update();
}

std::size_t VtkView::markerCount() const { return d->markerLabels.size(); }

void VtkView::pickHover() {
    if (const std::optional<double> value = scalarAt(d->hoverPosition)) {
        emit scalarHovered(*value);
    } else {
        emit hoverLeft();
    }
}

const std::shared_ptr<const MeshScene>& VtkView::scene() const { return d->scene; }

void VtkView::setViewOptions(const ViewOptions& options) {
    if (options == d->options) return;
    d->options = options;
    applyViewOptions();
    update();
}

const ViewOptions& VtkView::viewOptions() const { return d->options; }

void VtkView::setOverlayScene(std::shared_ptr<const MeshScene> overlay) {
    if (overlay == d->overlayScene) return;
    if (d->overlayActor) d->renderer->RemoveActor(d->overlayActor);
    d->overlayActor = nullptr;
    d->overlayMapper = nullptr;
    d->overlayScene = std::move(overlay);
    if (d->overlayScene && !d->overlayScene->parts.empty()) {
        d->overlayMapper = vtkSmartPointer<vtkPolyDataMapper>::New();
        d->overlayMapper->SetInputData(d->overlayScene->parts.front().polyData);
        d->overlayActor = vtkSmartPointer<vtkActor>::New();
        d->overlayActor->SetMapper(d->overlayMapper);
        d->overlayActor->PickableOff();
        vtkProperty* property = d->overlayActor->GetProperty();
        property->SetLighting(false);  // the line colour is the cell's colour, whatever the light
        property->SetLineWidth(1.5f);
        d->renderer->AddActor(d->overlayActor);
    }
    d->applyOverlayOptions();
    update();
}

const std::shared_ptr<const MeshScene>& VtkView::overlayScene() const { return d->overlayScene; }

bool VtkView::overlayVisible() const { return d->overlayActor && d->options.cells; }

void VtkView::Private::applyOverlayOptions() {
    if (!overlayActor) return;
    overlayActor->SetVisibility(options.cells);
    overlayMapper->SetScalarModeToUseCellFieldData();
    overlayMapper->SelectColorArray(options.cellsByTriangles ? cellTriangleColorsName() : cellDepthColorsName());
    overlayMapper->SetColorModeToDirectScalars();
    overlayMapper->ScalarVisibilityOn();
    if (options.cells) renderer->ResetCameraClippingRange();  // the root cube may reach past the mesh
}

void VtkView::applyViewOptions() {
    d->applyOverlayOptions();
    const bool split = !d->compareActors.empty();
    d->applyOptions(d->actors, split ? d->keepRight.Get() : nullptr);
    d->applyOptions(d->compareActors, d->keepLeft);
}

void VtkView::Private::applyOptions(std::vector<Actor>& list, vtkPlane* clip) {
    const ViewOptions& o = options;
    for (Actor& a : list) {
        vtkProperty* property = a.actor->GetProperty();
        if (o.wireframe) {
            property->SetRepresentationToWireframe();
        } else {
            property->SetRepresentationToSurface();
        }
        property->SetEdgeVisibility(o.edges && !o.wireframe);
        if (o.flatShading) {
            property->SetInterpolationToFlat();
        } else {
            property->SetInterpolationToGouraud();
        }
        a.mapper->RemoveAllClippingPlanes();
        if (clip) a.mapper->AddClippingPlane(clip);

        const bool normalColors = o.normalColors && !a.hasScalars &&
                                  a.mapper->GetInput()->GetPointData()->GetNormals() != nullptr;
        // Unlit for normal colours, so the colour is the normal itself.
        property->SetAmbient(normalColors ? 1.0 : 0.12);
        property->SetDiffuse(normalColors ? 0.0 : 0.88);
        property->SetSpecular(normalColors ? 0.0 : 0.08);
        property->SetOpacity(1.0);

        if (a.hasScalars) {
            a.actor->SetTexture(nullptr);
            a.mapper->SetLookupTable(lut);
            a.mapper->SetScalarModeToUsePointFieldData();
            a.mapper->SelectColorArray(scalarArrayName());
            a.mapper->SetColorModeToMapScalars();
            a.mapper->UseLookupTableScalarRangeOn();
            a.mapper->InterpolateScalarsBeforeMappingOn();
            a.mapper->ScalarVisibilityOn();
            property->SetColor(1.0, 1.0, 1.0);
            continue;
        }
        if (normalColors) {
            ensureNormalColors(a.mapper->GetInput());
            a.actor->SetTexture(nullptr);
            a.mapper->SetScalarModeToUsePointFieldData();
            a.mapper->SelectColorArray(normalColorsName);
            a.mapper->SetColorModeToDirectScalars();
            a.mapper->ScalarVisibilityOn();
            property->SetColor(1.0, 1.0, 1.0);
            continue;
        }
        // Texture first (the UV checker replaces it); vertex colours where no texture shows; else the
        // material colour or neutral grey.
        if (o.uvChecker && o.uvCheckerCells != checkerCells) {
            checkerCells = o.uvCheckerCells;
            checker->SetInputData(makeCheckerImage(checkerCells));
        }
        vtkTexture* texture = a.hasTcoords && o.uvChecker ? checker.Get() : (o.textures ? a.texture.Get() : nullptr);
        render::applySurfaceLook(a, texture, o.vertexColors, texture && texture == checker.Get());
    }
}

void VtkView::resetView() {
    vtkCamera* camera = d->renderer->GetActiveCamera();
    camera->SetFocalPoint(0, 0, 0);
    camera->SetPosition(0, 0, 1);
    camera->SetViewUp(0, 1, 0);
    // Three-quarter view from the -Z side, where OBJ exports (and the bundled Spot) have their front.
    camera->Azimuth(215.0);
    camera->Elevation(15.0);
    camera->OrthogonalizeViewUp();
    // Frame the mesh, not the overlay's root cube; but keep the cubes inside the clipping range.
    const bool overlay = d->overlayActor && d->overlayActor->GetVisibility();
    if (overlay) d->overlayActor->VisibilityOff();
    d->renderer->ResetCamera();
    if (overlay) d->overlayActor->VisibilityOn();
    d->renderer->ResetCameraClippingRange();
    update();
    emit cameraChanged();
}

quint64 VtkView::frameCount() const { return d->frames; }

QSize VtkView::sizeHint() const { return {800, 600}; }

namespace {

// Qt's logical position -> VTK's device pixels with the origin at the bottom (FlipY), plus modifiers.
void setEventInformation(vtkRenderWindowInteractor* interactor, const QWidget* widget, QPointF position,
                         Qt::KeyboardModifiers modifiers, int repeat = 0) {
    const qreal ratio = widget->devicePixelRatioF();
    interactor->SetEventInformationFlipY(static_cast<int>(std::lround(position.x() * ratio)),
                                         static_cast<int>(std::lround(position.y() * ratio)),
                                         modifiers.testFlag(Qt::ControlModifier) ? 1 : 0,
                                         modifiers.testFlag(Qt::ShiftModifier) ? 1 : 0, 0, repeat);
    interactor->SetAltKey(modifiers.testFlag(Qt::AltModifier) ? 1 : 0);
}

unsigned long pressEvent(Qt::MouseButton button) {
    switch (button) {
    case Qt::LeftButton: return vtkCommand::LeftButtonPressEvent;
    case Qt::MiddleButton: return vtkCommand::MiddleButtonPressEvent;
    case Qt::RightButton: return vtkCommand::RightButtonPressEvent;
    default: return vtkCommand::NoEvent;
    }
}

unsigned long releaseEvent(Qt::MouseButton button) {
    switch (button) {
    case Qt::LeftButton: return vtkCommand::LeftButtonReleaseEvent;
    case Qt::MiddleButton: return vtkCommand::MiddleButtonReleaseEvent;
    case Qt::RightButton: return vtkCommand::RightButtonReleaseEvent;
    default: return vtkCommand::NoEvent;
    }
}

}  // namespace

void VtkView::mousePressEvent(QMouseEvent* event) {
    d->pressPosition.reset();
    if (event->button() == Qt::LeftButton) d->pressPosition = event->position();
    setEventInformation(d->interactor, this, event->position(), event->modifiers());
    if (const unsigned long id = pressEvent(event->button()); id != vtkCommand::NoEvent) d->interactor->InvokeEvent(id);
    event->accept();
}

void VtkView::mouseDoubleClickEvent(QMouseEvent* event) {
    // VTK recognises a double click as a press with a repeat count.
    setEventInformation(d->interactor, this, event->position(), event->modifiers(), 1);
    if (const unsigned long id = pressEvent(event->button()); id != vtkCommand::NoEvent) d->interactor->InvokeEvent(id);
    event->accept();
}

void VtkView::mouseReleaseEvent(QMouseEvent* event) {
    setEventInformation(d->interactor, this, event->position(), event->modifiers());
    if (const unsigned long id = releaseEvent(event->button()); id != vtkCommand::NoEvent) d->interactor->InvokeEvent(id);
    event->accept();
    if (event->button() == Qt::LeftButton && d->pressPosition &&
        (event->position() - *d->pressPosition).manhattanLength() <= 4)
        emit clicked(event->position().toPoint());
    d->pressPosition.reset();
}

void VtkView::mouseMoveEvent(QMouseEvent* event) {
    setEventInformation(d->interactor, this, event->position(), event->modifiers());
    d->interactor->InvokeEvent(vtkCommand::MouseMoveEvent);
    if (event->buttons() == Qt::NoButton && d->scene && d->scene->hasScalars) {
        // Picking is a ray cast over the mesh: once the cursor rests, not on every event.
        d->hoverPosition = event->position().toPoint();
        d->hoverTimer.start();
    }
    event->accept();
}

void VtkView::wheelEvent(QWheelEvent* event) {
    setEventInformation(d->interactor, this, event->position(), event->modifiers());
    const int delta = event->angleDelta().y();
    if (delta > 0) {
        d->interactor->InvokeEvent(vtkCommand::MouseWheelForwardEvent);
    } else if (delta < 0) {
        d->interactor->InvokeEvent(vtkCommand::MouseWheelBackwardEvent);
    }
    event->accept();
}

void VtkView::enterEvent(QEnterEvent* event) {
    d->interactor->InvokeEvent(vtkCommand::EnterEvent);
    QOpenGLWidget::enterEvent(event);
}

void VtkView::leaveEvent(QEvent* event) {
    d->interactor->InvokeEvent(vtkCommand::LeaveEvent);
    d->hoverTimer.stop();
    if (d->scene && d->scene->hasScalars) emit hoverLeft();
    QOpenGLWidget::leaveEvent(event);
}

}  // namespace lodforge::widgets
