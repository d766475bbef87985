#include "lodforge/widgets/VtkView.h"

#include "MeshActorBuilder.h"

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGenericRenderWindowInteractor.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkNew.h>
#include <vtkOpenGLState.h>
#include <vtkPointData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTexture.h>

#include <QMouseEvent>
#include <QOpenGLContext>
#include <QSurfaceFormat>
#include <QWheelEvent>
#include <qopengl.h>  // GL enums; VTK's own GL loader (glew) must not be included after it

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace lodforge::widgets {

namespace {

// Neutral material for surfaces with neither texture nor colours.
constexpr double neutralGrey[3] = {0.78, 0.78, 0.80};

double linearToSrgb(double c) {
    if (!(c > 0.0)) return 0.0;
    if (c >= 1.0) return 1.0;
    return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

}  // namespace

struct VtkView::Private {
    explicit Private(VtkView* view) : q(view) {}

    struct Actor {
        vtkSmartPointer<vtkActor> actor;
        vtkSmartPointer<vtkPolyDataMapper> mapper;
        vtkSmartPointer<vtkTexture> texture;  // null when the part has no texture
        bool hasTcoords = false;
        bool hasColors = false;
        bool hasMaterial = false;
        std::array<double, 4> baseColor{1, 1, 1, 1};
    };

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
        static_cast<Private*>(clientData)->q->update();
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
};

VtkView::VtkView(QWidget* parent) : QOpenGLWidget(parent), d(std::make_unique<Private>(this)) {
    setFocusPolicy(Qt::StrongFocus);
    setMouseTracking(false);

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
    d->interactor->UpdateSize(static_cast<int>(std::lround(w * ratio)), static_cast<int>(std::lround(h * ratio)));
}

void VtkView::paintGL() {
    if (!d->window->GetReadyForRendering()) return;
    d->inPaint = true;
    vtkOpenGLState* state = d->window->GetState();
    // Qt changed GL state behind VTK's cache: re-read it, and restore it for Qt afterwards.
    state->Reset();
    state->Push();
    state->vtkglDepthFunc(GL_LEQUAL);  // Qt leaves GL_LESS; VTK's passes expect LEQUAL

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
    d->scene = std::move(scene);
    if (d->scene) {
        for (const MeshScene::Part& part : d->scene->parts) {
            Private::Actor a;
            a.mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
            a.mapper->SetInputData(part.polyData);
            a.mapper->SetScalarModeToUsePointData();
            a.mapper->SetColorModeToDirectScalars();
            a.actor = vtkSmartPointer<vtkActor>::New();
            a.actor->SetMapper(a.mapper);
            a.hasTcoords = part.polyData->GetPointData()->GetTCoords() != nullptr;
            a.hasColors = part.polyData->GetPointData()->GetScalars() != nullptr;
            a.hasMaterial = part.hasMaterial;
            a.baseColor = part.baseColor;
            if (part.texture && a.hasTcoords) {
                a.texture = vtkSmartPointer<vtkTexture>::New();
                a.texture->SetInputData(part.texture);
                a.texture->InterpolateOn();
                a.texture->MipmapOn();
                a.texture->RepeatOn();
                a.texture->SetColorModeToDirectScalars();
            }
            vtkProperty* property = a.actor->GetProperty();
            property->SetAmbient(0.12);
            property->SetDiffuse(0.88);
            property->SetSpecular(0.08);
            property->SetSpecularPower(30.0);
            property->BackfaceCullingOff();
            d->renderer->AddActor(a.actor);
            d->actors.push_back(std::move(a));
        }
    }
    applyViewOptions();
    if (resetCamera) resetView();
    update();
}

const std::shared_ptr<const MeshScene>& VtkView::scene() const { return d->scene; }

void VtkView::setViewOptions(const ViewOptions& options) {
    if (options == d->options) return;
    d->options = options;
    applyViewOptions();
    update();
}

const ViewOptions& VtkView::viewOptions() const { return d->options; }

void VtkView::applyViewOptions() {
    const ViewOptions& o = d->options;
    for (Private::Actor& a : d->actors) {
        vtkProperty* property = a.actor->GetProperty();
        if (o.wireframe) {
            property->SetRepresentationToWireframe();
        } else {
            property->SetRepresentationToSurface();
        }
        if (o.flatShading) {
            property->SetInterpolationToFlat();
        } else {
            property->SetInterpolationToGouraud();
        }

        // Texture first; vertex colours where no texture shows; else the material colour or neutral grey.
        const bool showTexture = o.textures && a.texture;
        const bool showColors = !showTexture && o.vertexColors && a.hasColors;
        a.actor->SetTexture(showTexture ? a.texture.Get() : nullptr);
        a.mapper->SetScalarVisibility(showColors);

        const double opacity = a.hasMaterial ? std::clamp(a.baseColor[3], 0.0, 1.0) : 1.0;
        property->SetOpacity(opacity);
        const bool whiteMaterial = !a.hasMaterial ||
                                   (a.baseColor[0] >= 1.0 && a.baseColor[1] >= 1.0 && a.baseColor[2] >= 1.0);
        if (showColors) {
            property->SetColor(1.0, 1.0, 1.0);
        } else if (showTexture || !whiteMaterial) {
            // A texture is modulated by the material's colour factor, as glTF defines it.
            property->SetColor(linearToSrgb(a.baseColor[0]), linearToSrgb(a.baseColor[1]),
                               linearToSrgb(a.baseColor[2]));
        } else {
            property->SetColor(neutralGrey[0], neutralGrey[1], neutralGrey[2]);
        }
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
    d->renderer->ResetCamera();
    d->renderer->ResetCameraClippingRange();
    update();
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
}

void VtkView::mouseMoveEvent(QMouseEvent* event) {
    setEventInformation(d->interactor, this, event->position(), event->modifiers());
    d->interactor->InvokeEvent(vtkCommand::MouseMoveEvent);
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
    QOpenGLWidget::leaveEvent(event);
}

}  // namespace lodforge::widgets
