/* app.h - the app layer's entry point. */
#ifndef CF_TEST_APP_H
#define CF_TEST_APP_H

void appMain(void);

#endif
