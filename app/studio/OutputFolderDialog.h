// Asks for the folder an export writes into: a path field where a new name makes a new folder, Browse…
// for the usual chooser, and a question before writing into a folder that already holds files. Starts in
// `initial`; the folder accepted is stored under a settings key so the caller can start the next export
// from it.
#pragma once

#include <QDialog>
#include <QString>

class QLabel;
class QLineEdit;

namespace lodforge::studio {

class OutputFolderDialog : public QDialog {
    Q_OBJECT

public:
    // `settingsKey` (QSettings) receives the folder accepted ("export/packDir").
    OutputFolderDialog(const QString& title, const QString& settingsKey, const QString& initial,
                       QWidget* parent = nullptr);

    // The folder accepted: absolute, existing (created on accept when it was new).
    QString folder() const { return folder_; }
    QLineEdit* pathEdit() const { return path_; }

    // Creates a missing folder; asks first (a window-modal question, objectName "nonEmptyFolderBox")
    // when the folder holds files. Stays open with the reason shown when the folder cannot be made.
    void accept() override;

private:
    void finish(const QString& folder);
    void updateNote();

    QString settingsKey_;
    QString folder_;
    QLineEdit* path_ = nullptr;
    QLabel* note_ = nullptr;
};

}  // namespace lodforge::studio
